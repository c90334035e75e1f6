#!/usr/bin/env bash
# The plausible model on a busy machine: the 50 x 50 and 256 x 256 curtains on --threads 1 and 2,
#   idle       nothing else running,
#   loaded     one CPU-bound process (`yes > /dev/null`) per core beside it,
#   side       two chainmail runs of the same size side by side (the time is the first one's),
# each the median of ROUNDS runs (default 3) of ms per step (summary.json). Runs of the three
# conditions and two thread counts are interleaved round by round, so that slow drift of a
# shared machine spreads over all of them. The load processes are killed at the end (also on
# Ctrl-C). Prints one line per size and condition: ms a step on 1 and 2 threads and their ratio
# (2 threads / 1 thread), and the final-state hashes (the same on both counts).
# Usage: scripts/busy_bench.sh [BUILD_DIR (default build/release)] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build/release}" rounds="${2:-3}"
chainmail="$build/bench/chainmail"
work=$(mktemp -d)
load_pids=()
stop_load() {
  for pid in "${load_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${load_pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  load_pids=()
}
trap 'stop_load; rm -rf "$work"' EXIT
start_load() {
  for _ in $(seq "$(nproc)"); do
    timeout 600 yes >/dev/null &  # bounded even if this script is killed outright
    load_pids+=($!)
  done
  sleep 0.5
}

# one run: size, threads, output folder -> "ms_per_step hash"
run() {
  "$chainmail" run bench/scenes/curtain.json --backends plausible --reference none --cache none \
    --quiet --threads "$2" --set weave.rows="$1" --set weave.cols="$1" \
    --set duration="$(duration "$1")" --out "$3" >/dev/null
  python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["backends"]["plausible"]
print(b["ms_per_step"], b["hash"])' "$3/summary.json"
}
duration() { [ "$1" -le 64 ] && echo 0.2 || echo 0.1; }

declare -A times hashes
for round in $(seq "$rounds"); do
  for size in 50 256; do
    for condition in idle loaded side; do
      for threads in 1 2; do
        key="$size $condition $threads"
        [ "$condition" = loaded ] && start_load
        if [ "$condition" = side ]; then
          run "$size" "$threads" "$work/other" >/dev/null &
          other=$!
          result=$(run "$size" "$threads" "$work/run")
          wait "$other"
        else
          result=$(run "$size" "$threads" "$work/run")
        fi
        [ "$condition" = loaded ] && stop_load
        times[$key]+="${result% *} "
        hashes[$key]="${result#* }"
        echo "round $round: $key threads: ${result% *} ms a step" >&2
      done
    done
  done
done

median() { tr ' ' '\n' | grep . | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}'; }
for size in 50 256; do
  for condition in idle loaded side; do
    one=$(echo "${times[$size $condition 1]}" | median)
    two=$(echo "${times[$size $condition 2]}" | median)
    same=$([ "${hashes[$size $condition 1]}" = "${hashes[$size $condition 2]}" ] && echo same ||
           echo DIFFERENT)
    printf '%3s x %-3s %-6s 1 thread %8.2f ms  2 threads %8.2f ms  ratio %5.2f  hashes %s\n' \
      "$size" "$size" "$condition" "$one" "$two" "$(awk -v a="$two" -v b="$one" 'BEGIN { print a / b }')" "$same"
  done
done

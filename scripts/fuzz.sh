#!/usr/bin/env bash
# Builds the libFuzzer targets (preset fuzz: clang, ASan + UBSan) and runs each for a fixed time:
#   scene_file    the scene-file parser with --set overrides
#   frame_stream  the frame-stream / reference-cache reader
#   saved_run     `chainmail render RUN_DIR`'s loader (summary.json, metrics.csv, frame CSVs)
# Seeds: the bench scenes and the command line's bad-input corpus (tests/fuzz/seeds.py), plus
# tests/fuzz/regressions/<target>/ (inputs that once crashed, each replayed first). The growing
# corpus is kept in build/fuzz/corpus/, findings go to build/fuzz/findings/<target>/; a finding
# fails the script (copy it into tests/fuzz/regressions/<target>/ once fixed).
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET (default 300)] [TARGET...]
# The targets fuzz side by side, each for SECONDS of one core: with more targets than cores
# (CHAINMAIL_FUZZ_CORES, default nproc) they share the cores for SECONDS x targets / cores, so each
# gets about the CPU time it would get alone in SECONDS, in a fraction of the time one by one takes.
# Prints, per target, the executions per second and the coverage reached (edges, features).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-300}"
shift || true
targets=("${@:-scene_file frame_stream saved_run}")
targets=(${targets[*]})
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$(nproc)" >/dev/null
build=build/fuzz
rm -rf "$build/seeds"
python3 tests/fuzz/seeds.py "$build/seeds" >/dev/null
cores="${CHAINMAIL_FUZZ_CORES:-$(nproc)}"
wall=$(( (seconds * ${#targets[@]} + cores - 1) / cores ))
[ "$wall" -ge "$seconds" ] || wall=$seconds
fuzz_target() {  # one target: its regressions replayed, then fuzzed; the summary in $build/$1.out
  local target=$1 status=0
  local binary="$build/tests/fuzz/chainmail_fuzz_$target"
  local corpus="$build/corpus/$target" findings="$build/findings/$target"
  mkdir -p "$corpus" "$findings"
  local regressions="tests/fuzz/regressions/$target"
  if [ -d "$regressions" ] && [ -n "$(ls -A "$regressions")" ]; then
    "$binary" -timeout=20 "$regressions"/* >/dev/null 2>&1 || {
      echo "fuzz: $target: a regression input crashes again (run $binary on $regressions)"
      status=1
    }
  fi
  local log="$build/$target.log"
  # -rss_limit_mb: a scene may ask for a large sheet; the loader's own limits must hold well below
  if ! "$binary" -max_total_time="$wall" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$findings/" "$corpus" "$build/seeds/$target" >"$log" 2>&1; then
    echo "fuzz: $target: FINDING, see $log and $findings/"
    status=1
  fi
  local runs rate cov
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1) || true
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1) || true
  cov=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -1) || true
  echo "fuzz: $target: ${runs:-?} runs in ${wall} s beside $(( ${#targets[@]} - 1 )) other(s)" \
       "on $cores core(s), ${rate:-?} exec/s, ${cov:-no coverage line} (edges, features)," \
       "corpus $(ls "$corpus" | wc -l) inputs"
  return $status
}
pids=()
for target in "${targets[@]}"; do
  fuzz_target "$target" >"$build/$target.out" 2>&1 &
  pids+=($!)
done
status=0
for k in "${!targets[@]}"; do
  wait "${pids[$k]}" || status=1
  cat "$build/${targets[$k]}.out"
done
exit $status

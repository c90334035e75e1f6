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
status=0
for target in "${targets[@]}"; do
  binary="$build/tests/fuzz/chainmail_fuzz_$target"
  corpus="$build/corpus/$target" findings="$build/findings/$target"
  mkdir -p "$corpus" "$findings"
  regressions="tests/fuzz/regressions/$target"
  if [ -d "$regressions" ] && [ -n "$(ls -A "$regressions")" ]; then
    "$binary" -timeout=20 "$regressions"/* >/dev/null 2>&1 || {
      echo "fuzz: $target: a regression input crashes again (run $binary on $regressions)"
      status=1
    }
  fi
  log="$build/$target.log"
  # -rss_limit_mb: a scene may ask for a large sheet; the loader's own limits must hold well below
  if ! "$binary" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$findings/" "$corpus" "$build/seeds/$target" >"$log" 2>&1; then
    echo "fuzz: $target: FINDING, see $log and $findings/"
    status=1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -1)
  echo "fuzz: $target: ${runs:-?} runs in ${seconds} s, ${rate:-?} exec/s, ${cov:-no coverage line}" \
       "(edges, features), corpus $(ls "$corpus" | wc -l) inputs"
done
exit $status

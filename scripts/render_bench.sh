#!/usr/bin/env bash
# The renderer's ms per frame at 1280x720 (Google Benchmark: 900 and 10,000 rings, with and without
# level of detail, 4x MSAA and none), written to results/micro_render.csv. Assumes a release build
# (scripts/build.sh); takes about two minutes on 2 cores, most of it the runs without level of detail.
set -euo pipefail
cd "$(dirname "$0")/.."
out=results/micro_render.csv
./build/release/bench/chainmail_micro --benchmark_filter=BM_RenderSheet \
  --benchmark_format=csv >"$out.tmp"
mv "$out.tmp" "$out"
echo "render benchmark: $out"

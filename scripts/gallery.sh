#!/usr/bin/env bash
# The paper's Golden Curtain at its own size (30 x 30 rings, 2 s) and the corner-hung sheet
# (16 x 16 rings from its two top corners, 2 s) in every backend, rendered side by side in gold:
# results/curtain_30x30/ and results/corner_hang/ (summary, table, the last frame and compare.mp4).
# Assumes a release build (scripts/build.sh); the rigid backends make this take several minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
chainmail=./build/release/bench/chainmail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# gallery SCENE_FILE OUT_FOLDER
gallery() {
  local scene=$1 out=$2 status=0
  "$chainmail" run "$scene" --backends all --render --material gold --out "$work/run" ||
    status=$?
  [ "$status" -le 1 ] || exit "$status"  # 1: a backend was unstable, which the table reports
  mkdir -p "$out"
  cp "$work/run/summary.json" "$work/run/table.md" "$out/"
  local last
  last=$(ls "$work/run/images/"*.png | tail -n 1)
  cp "$last" "$out/final_side_by_side.png"
  [ -f "$work/run/images/compare.mp4" ] && cp "$work/run/images/compare.mp4" "$out/"
  rm -rf "$work/run"
  echo "gallery: $out"
}

gallery bench/scenes/curtain.json results/curtain_30x30
gallery bench/scenes/corner_hang.json results/corner_hang

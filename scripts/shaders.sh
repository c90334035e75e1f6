#!/usr/bin/env bash
# One picture per cloth shader: the document's cloth draped over a sphere (mass-spring backend),
# final frame, written to results/shaders/<shader>.png. Assumes a release build (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
chainmail=./build/release/bench/chainmail
out=results/shaders
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
for shader in blinn_phong texture bump displacement mirror; do
  "$chainmail" run bench/scenes/cloth/sphere.json --backends massspring --render --shader "$shader" \
    --set sample_interval=2.0 --out "$work/$shader" --quiet
  last=$(ls "$work/$shader/images/"*.png | tail -n 1)
  cp "$last" "$out/$shader.png"
  echo "shaders: $out/$shader.png"
done

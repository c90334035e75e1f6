#!/usr/bin/env bash
# What Bullet's and ODE's own settings cost and buy on the bench's curtain and sphere drape:
# results/references/{profile.csv,profile.md}. Assumes a release build (scripts/build.sh); about
# 12 minutes on 2 cores, on one thread (run it on an otherwise idle machine: it measures time).
set -euo pipefail
cd "$(dirname "$0")/.."
tool=${CHAINMAIL_BUILD_DIR:-build/release}/bench/chainmail_reference_profile
out=results/references
mkdir -p "$out"
"$tool" bench/scenes "$@" > "$out/profile.csv.part"
mv "$out/profile.csv.part" "$out/profile.csv"
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3
"$python" - "$out/profile.csv" "$out/profile.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
lines = ["# The rigid references' settings", "",
         "Each bench scene (16 x 16 rings, 1 s) through Bullet and ODE at their default knobs, then "
         "with one change at a time, on one thread, one run each. `drape_rms` is measured against "
         "the same backend's default run (mm): at the end, and the largest over the samples. "
         "The `length_scale 1001` row changes nothing but rounding: its drape_rms is the noise "
         "floor, the sheet's own sensitivity, below which a change costs no accuracy. "
         "Surface error: the capsule compound's largest distance from the torus, in wire radii. "
         "Written by `scripts/reference_profile.sh` (`chainmail_reference_profile`).", "",
         "| scene | backend | change | ms/step | speed-up | drape_rms end (mm) | drape_rms max (mm) "
         "| surface error | max_stretch | broken | verdict |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    lines.append("| {scene} | {backend} | {change} | {ms_per_step} | {speedup} | {drape_rms_final_mm} "
                 "| {drape_rms_max_mm} | {surface_error_over_a} | {max_stretch} | {broken_links} "
                 "| {verdict} |".format(**r))
open(sys.argv[2], "w").write("\n".join(lines) + "\n")
PY
echo "reference profile: $out"

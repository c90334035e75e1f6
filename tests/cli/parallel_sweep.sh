#!/usr/bin/env bash
# The README's GNU parallel recipe for a sweep: the printed jobs (the reference first, then the
# points through `parallel`), then --gather; the gathered sweep.csv must equal a local sweep's
# but for the timing columns, and every point's final hash must be the local one's.
# Skipped (status 77) without GNU parallel.
#   tests/cli/parallel_sweep.sh CHAINMAIL_BINARY SCENE
set -euo pipefail
chainmail=$(realpath "$1")
scene=$2
command -v parallel >/dev/null || { echo "parallel_sweep: GNU parallel not installed"; exit 77; }
work=$(mktemp -d "${TMPDIR:-/tmp}/chainmail-parallel.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
sweep=("$chainmail" sweep "$scene" --vary 'backends.{backend}.dt=0.004,0.002'
       --backends plausible,massspring --set weave.rows=5 --set weave.cols=5 --set duration=0.1
       --set reference=plausible --cache "$work/cache")

"${sweep[@]}" --out local --jobs 2 2>/dev/null
# the recipe
"${sweep[@]}" --out jobs --print-jobs > jobs.txt
head -n 1 jobs.txt | sh
tail -n +2 jobs.txt | parallel -j 2 || true  # an unstable point exits 1; --gather checks them all
"${sweep[@]}" --gather jobs

diff <(cut -d, -f1,2,5- local/sweep.csv) <(cut -d, -f1,2,5- jobs/sweep.csv)
for summary in local/points/*/summary.json; do
  hash() { grep -o '"hash": *"[0-9a-f]*"' "$1"; }
  [ "$(hash "$summary")" = "$(hash "jobs/${summary#local/}")" ] ||
    { echo "parallel_sweep: $summary: hash differs"; exit 1; }
done
[ "$(wc -l < jobs/sweep.csv)" -eq 5 ]
echo "parallel_sweep: ok ($(($(wc -l < jobs.txt) - 1)) points)"

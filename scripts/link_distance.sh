#!/usr/bin/env bash
# The largest centre distance of two linked rings over their relative orientation, for the default
# ring (aspect ratio 5): results/link_distance/{link_distance.csv,link_distance.png}. Assumes a
# release build (scripts/build.sh) and python3 with matplotlib (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
table=${CHAINMAIL_BUILD_DIR:-build/release}/bench/chainmail_link_table
out=results/link_distance
mkdir -p "$out"
"$table" > "$out/link_distance.csv"
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3  # Debian's, with python3-matplotlib
"$python" bench/plot_link_distance.py "$out/link_distance.csv" "$out/link_distance.png"
echo "link distance: $out"

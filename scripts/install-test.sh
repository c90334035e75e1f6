#!/usr/bin/env bash
# Installs a built tree into a temporary prefix and uses it as a new user and an outside project
# would: the installed `chainmail` run from a folder outside the source tree on an installed
# scene, and tests/consumer (a project of its own: find_package(chainmail), a backend it
# registers, the backend contract tests on it, an installed scene stepped) built against the
# installed package, its tests run. Removes the prefix afterwards.
#   ./scripts/install-test.sh [BUILD_DIR]     (default build/release, already built)
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir=$(pwd)
build=$(realpath "${1:-build/release}")
work=$(mktemp -d "${TMPDIR:-/tmp}/chainmail-install.XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
seconds() { date +%s.%N; }
took() { awk -v a="$1" -v b="$(seconds)" 'BEGIN { printf "%.1f s", b - a }'; }

start=$(seconds)
cmake --install "$build" --prefix "$prefix" >/dev/null
echo "install-test: installed into $prefix in $(took "$start"), $(du -sh "$prefix" | cut -f1)"

# a new user: the installed command, in a folder of its own, on the installed scenes
chainmail="$prefix/bin/chainmail"
scenes="$prefix/share/chainmail/scenes"
cd "$work"
"$chainmail" --version
if ! "$chainmail" --help | grep -qF "$scenes"; then
  echo "install-test: the installed chainmail does not read $scenes"
  exit 1
fi
"$chainmail" backends >/dev/null
"$chainmail" check "$scenes"/*.json "$scenes"/*/*.json >/dev/null
"$chainmail" run "$scenes/curtain.json" --backends plausible --reference none --quiet \
  --set weave.rows=6 --set weave.cols=6 --set duration=0.2
test -s results/curtain/run/summary.json

# an outside project against the installed package
start=$(seconds)
quiet() { "$@" >log.txt 2>&1 || { cat log.txt; exit 1; }; }
quiet cmake -S "$source_dir/tests/consumer" -B consumer -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release
quiet cmake --build consumer -j"$(nproc)"
echo "install-test: consumer configured and built in $(took "$start")"
ctest --test-dir consumer --output-on-failure
echo "install-test: ok"

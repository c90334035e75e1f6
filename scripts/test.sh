#!/usr/bin/env bash
# Installs, builds and runs the whole test suite in both CI configurations: the default build
# (release preset, every backend) and a build without the rigid-body references (minimal preset:
# Bullet and ODE off), where the tests and bench scenes that need them are skipped with a note.
# `./scripts/test.sh release` or `./scripts/test.sh minimal` runs one of them.
set -euo pipefail
cd "$(dirname "$0")/.."
presets=("${@:-release minimal}")
for preset in ${presets[*]}; do
  echo "== $preset"
  ./scripts/build.sh "$preset"
  ctest --preset "$preset" -j"$(nproc)"
done

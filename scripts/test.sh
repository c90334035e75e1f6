#!/usr/bin/env bash
# Installs, builds and runs the whole test suite in both CI configurations: the default build
# (release preset, every backend) and a build without the rigid-body references (minimal preset:
# Bullet and ODE off), where the tests and bench scenes that need them are skipped with a note.
# The release build is then installed into a temporary prefix and used from there, by the
# installed command and by a project of its own (scripts/install-test.sh).
# `./scripts/test.sh release` or `./scripts/test.sh minimal` runs one of them.
set -euo pipefail
cd "$(dirname "$0")/.."
presets=("${@:-release minimal}")
for preset in ${presets[*]}; do
  echo "== $preset"
  ./scripts/build.sh "$preset"
  ctest --preset "$preset" -j"$(nproc)"
  if [ "$preset" = release ]; then
    ./scripts/install-test.sh build/release
  fi
done

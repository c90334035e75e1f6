#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (release preset).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh release
ctest --preset release -j"$(nproc)"

#!/usr/bin/env bash
# Installs, builds and runs the main job: the default bench, writing results/bench/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh release
./build/release/bench/chainmail bench --out results/bench

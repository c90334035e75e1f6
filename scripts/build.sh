#!/usr/bin/env bash
# Configures and builds one preset (default: release) after installing the dependencies.
# Compiles through ccache when it is installed (the same compiler and flags, so the same objects):
# the test script's second build then compiles only the files whose preprocessed text differs.
# CMAKE_CXX_COMPILER_LAUNCHER= (set, empty) in the environment leaves ccache out.
#   ./scripts/build.sh [PRESET [CMAKE_ARGS...]]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
./scripts/install-deps.sh
launcher=()
if [ -z "${CMAKE_CXX_COMPILER_LAUNCHER+set}" ] && command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake --preset "$preset" "${launcher[@]}" "${@:2}" >/dev/null
cmake --build --preset "$preset" -j"$(nproc)"

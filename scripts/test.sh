#!/usr/bin/env bash
# Installs, builds and runs the whole test suite in both CI configurations: the default build
# (release preset, every backend) and a build without the rigid-body references (minimal preset:
# Bullet and ODE off), where the tests and bench scenes that need them are skipped with a note.
# The release build is then installed into a temporary prefix and used from there, by the
# installed command and by a project of its own (scripts/install-test.sh).
# With root (or sudo without a password) the release build also runs a sweep through a one-node
# Slurm cluster on this machine against the same sweep run locally (scripts/slurm-test.sh, about a
# minute and a half); CHAINMAIL_SLURM_TEST=0 leaves it out.
# When both run, the minimal build neither builds nor runs the tests labelled core, render and
# rigid-independent (the structure and commit-stamp checks; CHAINMAIL_TESTS_RIGID_DEPENDENT_ONLY):
# their code and build flags are the same in both builds, so the release run has checked them
# already. scripts/build.sh compiles through ccache (scripts/install-deps.sh installs it), so the
# minimal build recompiles only the files that Bullet and ODE change. Each phase prints the time
# it took.
# Then each fuzz target runs for CHAINMAIL_FUZZ_SECONDS of one core (default 60; 0 leaves it out)
# when clang and libFuzzer are installed (scripts/fuzz.sh: the three targets side by side, a minute
# and a half on two cores; the fuzz build runs beside the Slurm test when that runs).
# `./scripts/test.sh release` or `./scripts/test.sh minimal` runs one of them, every test.
set -euo pipefail
cd "$(dirname "$0")/.."
presets=(${@:-release minimal})
phase() {
  local start=$SECONDS
  "${@:2}"
  echo "test: $1 took $((SECONDS - start)) s"
}
fuzz_seconds="${CHAINMAIL_FUZZ_SECONDS:-60}"
can_fuzz() {
  [ "$fuzz_seconds" != 0 ] && command -v clang++ >/dev/null &&
    ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-*.a >/dev/null 2>&1
}
# the fuzz build starts beside the Slurm test, which mostly waits (packages, daemons, the queue)
fuzz_build_pid="" fuzz_build_start=0
start_fuzz_build() {
  can_fuzz || return 0
  mkdir -p build
  fuzz_build_start=$SECONDS
  (cmake --preset fuzz && cmake --build --preset fuzz -j"$(nproc)") >build/fuzz-build.log 2>&1 &
  fuzz_build_pid=$!
}
for preset in "${presets[@]}"; do
  echo "== $preset"
  only_rigid=OFF
  if [ "$preset" != release ] && [[ " ${presets[*]} " == *" release "* ]]; then
    only_rigid=ON
  fi
  phase "build $preset" ./scripts/build.sh "$preset" -DCHAINMAIL_TESTS_RIGID_DEPENDENT_ONLY=$only_rigid
  phase "ctest $preset" ctest --preset "$preset" -j"$(nproc)"
  if [ "$preset" = release ]; then
    phase "install test" ./scripts/install-test.sh build/release
    if [ "${CHAINMAIL_SLURM_TEST:-1}" != 0 ]; then
      if [ "$(id -u)" -eq 0 ] || sudo -n true 2>/dev/null; then
        start_fuzz_build
        phase "slurm test" ./scripts/slurm-test.sh build/release
      else
        echo "test: no root or sudo: the Slurm sweep test is left out (scripts/slurm-test.sh)"
      fi
    fi
  fi
done
if can_fuzz; then
  echo "== fuzz"
  if [ -n "$fuzz_build_pid" ]; then
    wait "$fuzz_build_pid" || { cat build/fuzz-build.log; echo "test: the fuzz build failed"; exit 1; }
    echo "test: fuzz build took $((SECONDS - fuzz_build_start)) s, beside the Slurm test"
  fi
  phase "fuzz" ./scripts/fuzz.sh "$fuzz_seconds"
elif [ "$fuzz_seconds" != 0 ]; then
  echo "test: clang or libFuzzer missing: fuzzing is left out (scripts/fuzz.sh)"
fi

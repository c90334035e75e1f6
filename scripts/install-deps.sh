#!/usr/bin/env bash
# Installs the Debian 12 packages chainmail needs; skips what is already installed.
set -euo pipefail
packages=(
  build-essential cmake pkg-config ccache
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libbenchmark-dev
  libbullet-dev libode-dev
  libosmesa6-dev libegl-dev libgl-dev libgles-dev libstb-dev
  python3-matplotlib python3-jsonschema python3-numpy ffmpeg
  python3-dev pybind11-dev python3-pytest parallel
  libjs-three chromium
  clang libfuzzer-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"

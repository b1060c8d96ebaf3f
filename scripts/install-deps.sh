#!/usr/bin/env bash
# Installs libbead's build dependencies from Debian 12's archive.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libceres-dev libhdf5-dev libdeflate-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libopencv-dev libmatio-dev libpcl-dev libgtest-dev libgmock-dev libbenchmark-dev python3-numpy python3-matplotlib
  pybind11-dev python3-dev python3-pytest
  clang clang-format libclang-rt-14-dev openmpi-bin
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

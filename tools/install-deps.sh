#!/usr/bin/env bash
# Installs the Debian 12 packages lhr builds with, when any is missing.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
  libopenmesh-dev libcgal-dev libembree-dev libopenimageio-dev
  libboost-program-options-dev libtbb-dev libtinyobjloader-dev nlohmann-json3-dev
  libgtest-dev libbenchmark-dev gnuplot-nox assimp-utils
  clang-14 libclang-rt-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  meshlab xvfb xauth)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing: ${missing[*]}" >&2
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# Installs lhr into a temporary prefix and builds and runs
# tests/package_consumer against it: the installed headers, libraries and
# lhrConfig.cmake must be enough for a program of its own (README "Use lhr
# from CMake"). Reuses build/ when it exists.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
# The lhr binary links all four libraries, which is all that is installed.
cmake --build build -j "$(nproc)" --target lhr
cmake --install build --prefix "$tmp/prefix" >/dev/null

cmake -S tests/package_consumer -B "$tmp/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/consumer" -j "$(nproc)"
"$tmp/consumer/lhr_consumer" "$root/data/cornell/cornell.scene.json"
"$tmp/prefix/bin/lhr" --version
echo "package: the installed lhr builds and runs a consumer"

#!/usr/bin/env bash
# Installs lhr into a temporary prefix and runs tests/python with pytest
# against the installed Python module and lhr executable (README "Use lhr
# from Python"), not the build tree's. Reuses build/ when it exists.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
if ! grep -q '^LHR_BUILD_PYTHON:BOOL=ON' build/CMakeCache.txt; then
  echo "test-python: build/ is configured with LHR_BUILD_PYTHON=OFF; reconfigure with -DLHR_BUILD_PYTHON=ON" >&2
  exit 1
fi
cmake --build build -j "$(nproc)" --target lhr lhr_python
cmake --install build --prefix "$tmp/prefix" >/dev/null

python=$(cat build/apps/python/python-interpreter.txt)
module=$(find "$tmp/prefix" -name 'lhr*.so' -path '*-packages/*')
if [ -z "$module" ]; then
  echo "test-python: cmake --install put no lhr module under a site-packages or dist-packages directory" >&2
  exit 1
fi
if ! "$python" -c 'import numpy, pytest' 2>/dev/null; then
  echo "test-python: $python cannot import numpy and pytest (Debian: python3-numpy python3-pytest," \
    "as tools/install-deps.sh installs)" >&2
  exit 1
fi

# From the test directory, with no cache written into the source tree.
cd "$tmp"
PYTHONPATH="$(dirname "$module")" LHR_EXECUTABLE="$tmp/prefix/bin/lhr" LHR_INSTALL_PREFIX="$tmp/prefix" \
  "$python" -m pytest -q -p no:cacheprovider "$root/tests/python"
echo "python: the installed module passes tests/python"

#!/usr/bin/env bash
# Installs missing packages, configures and builds lhr into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh

# The Python module is built for, and tested with, an interpreter that can
# import the packages install-deps.sh installs (numpy, pytest). Another
# python3 earlier on PATH (pyenv, a virtualenv) often cannot, so when build/
# has no interpreter yet, take the first python3 that can: the one on PATH,
# else Debian's own.
python_args=()
if ! grep -q '^Python_EXECUTABLE' build/CMakeCache.txt 2>/dev/null; then
  for candidate in "$(command -v python3 || true)" /usr/bin/python3; do
    if [ -n "$candidate" ] && "$candidate" -c 'import numpy, pytest' 2>/dev/null; then
      python_args=(-DPython_EXECUTABLE="$candidate")
      break
    fi
  done
fi
# Ninja for a new build tree (an existing one keeps its generator): it
# compiles any target's sources as soon as their inputs exist, where Make
# waits for every dependency target first, so both cores stay busy
# (docs/robustness.md, "What runs where").
export CMAKE_GENERATOR=${CMAKE_GENERATOR:-Ninja}
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${python_args[@]}" >/dev/null
cmake --build build -j "$(nproc)"

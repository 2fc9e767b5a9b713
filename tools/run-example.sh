#!/usr/bin/env bash
# Builds lhr and runs the main job on the bundled Cornell box: initial
# meshing, written as PLY, then checked with `lhr validate`.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
mkdir -p out
build/apps/lhr mesh data/cornell/cornell.scene.json --out out/cornell.ply
build/apps/lhr validate out/cornell.ply

#!/usr/bin/env bash
# Builds lhr and runs the main job on the bundled Cornell box: the lit,
# refined mesh (out/cornell/mesh.ply, mesh.off), its Gouraud view
# (image.png, image.exr) and stats.json, then checks the mesh with
# `lhr validate`.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
build/apps/lhr solve data/cornell/cornell.scene.json --out out/cornell
build/apps/lhr validate out/cornell/mesh.ply

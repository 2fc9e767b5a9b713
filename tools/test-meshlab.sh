#!/usr/bin/env bash
# MeshLab reads lhr's meshes as lhr means them: meshlabserver (MeshLab
# 2020.09, Debian 12) re-saves a solved mesh.ply and mesh.off with vertex
# colours, and the re-saved files hold the same vertices, faces and colours
# (tools/compare-mesh-colours.py) and still validate. meshlabserver needs an X
# display even without a window, hence xvfb-run. Reuses build/ when it exists.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target lhr
lhr=$root/build/apps/lhr
compare=$root/tools/compare-mesh-colours.py

# A coarse solve: a few thousand vertices of many colours, in seconds.
"$lhr" solve data/cornell/cornell.scene.json --out "$tmp/solve" \
  --max-edge 200 --eps-link 160 --eps-pixel 4 --quiet

export XDG_RUNTIME_DIR=$tmp/xdg
mkdir -m 700 "$XDG_RUNTIME_DIR"
# meshlabserver IN OUT [MASK...], its chatter kept for a failure.
resave() {
  local in=$1 out=$2
  shift 2
  if ! xvfb-run -a meshlabserver -i "$in" -o "$out" "$@" >"$tmp/meshlab.log" 2>&1 || [ ! -s "$out" ]; then
    cat "$tmp/meshlab.log" >&2
    echo "meshlab: meshlabserver could not re-save $in as $out" >&2
    exit 1
  fi
}

for ext in ply off; do
  resave "$tmp/solve/mesh.$ext" "$tmp/resaved.$ext" -m vc
  python3 "$compare" "$tmp/solve/mesh.$ext" "$tmp/resaved.$ext"
  "$lhr" validate "$tmp/resaved.$ext"
  # Without -m vc MeshLab drops the colours: the comparison must see it.
  resave "$tmp/solve/mesh.$ext" "$tmp/uncoloured.$ext"
  if python3 "$compare" "$tmp/solve/mesh.$ext" "$tmp/uncoloured.$ext" 2>/dev/null; then
    echo "meshlab: the comparison missed the colours MeshLab dropped from $ext" >&2
    exit 1
  fi
done
echo "meshlab: meshlabserver re-saves mesh.ply and mesh.off with the same vertices, faces and colours"

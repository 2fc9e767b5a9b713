#!/usr/bin/env python3
"""Writes a stress scene: boxes of random heights on a floor under one lamp.

    tools/box-field.py DIR [--boxes 1000] [--seed 7]

DIR/boxes.obj and DIR/boxes.mtl: a floor 2 m wider than a square grid of
1 m cells, one 0.5 m box in each of the first --boxes cells (six faces, each
an OBJ group of its own, height 0.3 to 1.8 m), and a 2 m square lamp 8 m
above the middle. Every surface but the lamp reflects (floor 0.6, boxes
0.7), so each lit box face becomes a shooter with links to the floor's many
vertices: the scene docs/robustness.md ("First links within the memory
budget") measures `--max-memory` on, with

    lhr solve DIR/boxes.obj --out OUT --max-memory 100M
"""

import argparse
import math
import os
import random


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir")
    parser.add_argument("--boxes", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    if args.boxes < 1:
        parser.error("--boxes must be at least 1")
    side = math.ceil(math.sqrt(args.boxes))
    rng = random.Random(args.seed)
    vertices, faces = [], []

    def quad(corners, material, group=None):
        if group:
            faces.append(f"g {group}")
        first = len(vertices) + 1
        vertices.extend(corners)
        faces.append(f"usemtl {material}\nf {first} {first + 1} {first + 2} {first + 3}")

    quad([(-1, 0, -1), (-1, 0, side + 1), (side + 1, 0, side + 1), (side + 1, 0, -1)], "floor", "floor")
    for k in range(args.boxes):
        i, j = divmod(k, side)
        x0, z0 = i + 0.25, j + 0.25
        x1, z1, h = x0 + 0.5, z0 + 0.5, 0.3 + 1.5 * rng.random()
        quad([(x0, h, z0), (x0, h, z1), (x1, h, z1), (x1, h, z0)], "box", f"box{k}_top")
        quad([(x0, 0, z0), (x0, h, z0), (x1, h, z0), (x1, 0, z0)], "box", f"box{k}_south")
        quad([(x1, 0, z1), (x1, h, z1), (x0, h, z1), (x0, 0, z1)], "box", f"box{k}_north")
        quad([(x0, 0, z1), (x0, h, z1), (x0, h, z0), (x0, 0, z0)], "box", f"box{k}_west")
        quad([(x1, 0, z0), (x1, h, z0), (x1, h, z1), (x1, 0, z1)], "box", f"box{k}_east")
        quad([(x0, 0, z0), (x1, 0, z0), (x1, 0, z1), (x0, 0, z1)], "box", f"box{k}_bottom")
    c = side / 2.0
    quad([(c - 1, 8, c - 1), (c + 1, 8, c - 1), (c + 1, 8, c + 1), (c - 1, 8, c + 1)], "lamp", "lamp")

    os.makedirs(args.dir, exist_ok=True)
    with open(os.path.join(args.dir, "boxes.obj"), "w") as f:
        f.write("mtllib boxes.mtl\n")
        f.write("".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in vertices))
        f.write("\n".join(faces) + "\n")
    with open(os.path.join(args.dir, "boxes.mtl"), "w") as f:
        f.write("newmtl floor\nKd 0.6 0.6 0.6\nnewmtl box\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0 0 0\nKe 20 20 20\n")


if __name__ == "__main__":
    main()

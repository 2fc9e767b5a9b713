#!/usr/bin/env python3
"""Checks that a mesh another tool re-saved still is lhr's mesh: the same
vertices in the same order, the same faces and the same 8-bit vertex colours.

    tools/compare-mesh-colours.py ORIGINAL RESAVED

Both files are PLY (ascii or binary) or ASCII OFF. Exit 0 when they agree,
1 with one line per kind of difference otherwise. Used by
tools/test-meshlab.sh; standard library only.
"""

import struct
import sys

PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B",
    "short": "h", "int16": "h", "ushort": "H", "uint16": "H",
    "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


class Mesh:
    def __init__(self):
        self.points = []   # (x, y, z)
        self.colours = []  # (r, g, b) 0..255, or empty when the file has none
        self.faces = []    # tuples of vertex indices


def read_ply(data):
    end = data.index(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = header[1].split()[1]
    elements = []  # (name, count, [(name, type) or (name, ("list", count_type, item_type))])
    for line in header[2:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info", "end_header"):
            continue
        if words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and words[1] == "list":
            elements[-1][2].append((words[4], ("list", words[2], words[3])))
        elif words[0] == "property":
            elements[-1][2].append((words[2], words[1]))
    body = data[end:]
    if fmt == "ascii":
        tokens = body.split()
        pos = 0

        def take(kind):
            nonlocal pos
            word = tokens[pos]
            pos += 1
            return float(word) if PLY_TYPES[kind] in "fd" else int(word)
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        pos = 0

        def take(kind):
            nonlocal pos
            code = order + PLY_TYPES[kind]
            (value,) = struct.unpack_from(code, body, pos)
            pos += struct.calcsize(code)
            return value

    mesh = Mesh()
    for name, count, props in elements:
        for _ in range(count):
            record = {}
            for pname, ptype in props:
                if isinstance(ptype, tuple):
                    n = take(ptype[1])
                    record[pname] = tuple(take(ptype[2]) for _ in range(n))
                else:
                    record[pname] = take(ptype)
            if name == "vertex":
                mesh.points.append((record["x"], record["y"], record["z"]))
                if "red" in record:
                    mesh.colours.append((record["red"], record["green"], record["blue"]))
            elif name == "face":
                mesh.faces.append(record.get("vertex_indices", record.get("vertex_index")))
    return mesh


def read_off(data):
    lines = [l.split("#", 1)[0].split() for l in data.decode("ascii").splitlines()]
    lines = [l for l in lines if l]
    keyword = lines[0][0]
    if not keyword.endswith("OFF") or "BINARY" in lines[0]:
        raise ValueError("not an ASCII OFF file")
    counts = lines[0][1:] or lines[1]
    first = 1 if lines[0][1:] else 2
    nv, nf = int(counts[0]), int(counts[1])
    mesh = Mesh()
    for words in lines[first:first + nv]:
        mesh.points.append(tuple(float(w) for w in words[:3]))
        if keyword.startswith("C") and len(words) >= 6:
            colour = words[3:6]
            if any("." in w or "e" in w.lower() for w in colour):
                raise ValueError("float vertex colours; lhr and MeshLab write 0..255 integers")
            mesh.colours.append(tuple(int(w) for w in colour))
    for words in lines[first + nv:first + nv + nf]:
        n = int(words[0])
        mesh.faces.append(tuple(int(w) for w in words[1:1 + n]))
    return mesh


def read_mesh(path):
    with open(path, "rb") as f:
        data = f.read()
    return read_ply(data) if data.startswith(b"ply") else read_off(data)


def compare(original, resaved):
    problems = []
    if len(original.colours) != len(original.points) or len({*original.colours}) < 2:
        problems.append("the original has no vertex colours worth comparing")
    if len(resaved.points) != len(original.points):
        problems.append("vertex count %d, not %d" % (len(resaved.points), len(original.points)))
        return problems
    # Both store float coordinates; an ASCII writer may print fewer digits.
    moved = sum(1 for a, b in zip(original.points, resaved.points)
                if any(abs(p - q) > 1e-5 * max(1.0, abs(p)) for p, q in zip(a, b)))
    if moved:
        problems.append("%d vertices moved" % moved)
    if len(resaved.colours) != len(resaved.points):
        problems.append("vertex colours dropped")
    else:
        changed = sum(1 for a, b in zip(original.colours, resaved.colours) if a != b)
        if changed:
            problems.append("%d vertex colours changed" % changed)
    if [tuple(f) for f in resaved.faces] != [tuple(f) for f in original.faces]:
        problems.append("faces differ (%d against %d)" % (len(resaved.faces), len(original.faces)))
    return problems


def main(argv):
    if len(argv) != 3:
        sys.exit("usage: compare-mesh-colours.py ORIGINAL RESAVED")
    original, resaved = read_mesh(argv[1]), read_mesh(argv[2])
    problems = compare(original, resaved)
    for p in problems:
        print("%s: %s" % (argv[2], p), file=sys.stderr)
    if problems:
        return 1
    print("%s: same %d vertices, %d colours (%d distinct), %d faces as %s" % (
        argv[2], len(resaved.points), len(resaved.colours), len({*resaved.colours}),
        len(resaved.faces), argv[1]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

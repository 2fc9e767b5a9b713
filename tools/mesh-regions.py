#!/usr/bin/env python3
"""Compares a solved mesh with its vertex reference region by region, by area.

    tools/mesh-regions.py D/mesh.ply D/ref.ply --box NAME=x0,x1,y0,y1,z0,z1 ...
                          [--exclude x0,x1,y0,y1,z0,z1 ...]

D/mesh.ply is what `lhr solve` exported, D/ref.ply what `lhr reference
--at-vertices D/mesh.ply` wrote for it (same vertices and faces). Every
triangle whose centroid lies in a box (and in no --exclude box) counts with
its area times the mean of its corners' linear luminance, in both files.
Per box and per orientation of the triangle (facing up, down, or sideways)
the script prints solve / reference: the product's error where the camera
does not look, as the pixel norm of `lhr compare` cannot show it
(docs/accuracy.md, "What a table hides"). Standard library only.
"""
import argparse
import math
import struct
import sys

TYPES = {'char': 'b', 'uchar': 'B', 'short': 'h', 'ushort': 'H', 'int': 'i', 'uint': 'I', 'float': 'f',
         'double': 'd', 'int8': 'b', 'uint8': 'B', 'int16': 'h', 'uint16': 'H', 'int32': 'i', 'uint32': 'I',
         'float32': 'f', 'float64': 'd'}


def read_ply(path):
    """Vertices (dicts of their properties) and faces of a binary little-endian PLY."""
    with open(path, 'rb') as f:
        if f.readline().strip() != b'ply':
            sys.exit(f'{path}: not a PLY file')
        element, counts, vertex_props, face_types = None, {}, [], None
        while True:
            line = f.readline()
            if not line:
                sys.exit(f'{path}: header ends early')
            words = line.decode('ascii', 'replace').split()
            if not words:
                continue
            if words[0] == 'format' and words[1] != 'binary_little_endian':
                sys.exit(f'{path}: only binary_little_endian PLY is read here')
            if words[0] == 'element':
                element = words[1]
                counts[element] = int(words[2])
            elif words[0] == 'property' and element == 'vertex':
                vertex_props.append((words[-1], TYPES[words[1]]))
            elif words[0] == 'property' and element == 'face' and words[1] == 'list':
                face_types = (TYPES[words[2]], TYPES[words[3]])
            elif words[0] == 'end_header':
                break
        fmt = '<' + ''.join(t for _, t in vertex_props)
        size = struct.calcsize(fmt)
        data = f.read(size * counts.get('vertex', 0))
        names = [n for n, _ in vertex_props]
        vertices = [dict(zip(names, struct.unpack_from(fmt, data, i * size))) for i in range(counts.get('vertex', 0))]
        faces = []
        count_size = struct.calcsize('<' + face_types[0])
        index_size = struct.calcsize('<' + face_types[1])
        for _ in range(counts.get('face', 0)):
            (k,) = struct.unpack('<' + face_types[0], f.read(count_size))
            faces.append(struct.unpack('<' + face_types[1] * k, f.read(index_size * k)))
        return vertices, faces


def luminance(v):
    return 0.2126 * v['radiance_r'] + 0.7152 * v['radiance_g'] + 0.0722 * v['radiance_b']


def parse_box(text):
    values = [float(x) for x in text.split(',')]
    if len(values) != 6:
        sys.exit(f'a box is x0,x1,y0,y1,z0,z1: {text}')
    return values


def inside(box, p):
    return all(box[2 * k] <= p[k] <= box[2 * k + 1] for k in range(3))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('mesh')
    parser.add_argument('reference')
    parser.add_argument('--box', action='append', default=[], metavar='NAME=x0,x1,y0,y1,z0,z1', required=True)
    parser.add_argument('--exclude', action='append', default=[], metavar='x0,x1,y0,y1,z0,z1')
    args = parser.parse_args()
    boxes = []
    for b in args.box:
        name, _, coords = b.partition('=')
        boxes.append((name, parse_box(coords)))
    excluded = [parse_box(e) for e in args.exclude]
    mesh_vertices, faces = read_ply(args.mesh)
    ref_vertices, ref_faces = read_ply(args.reference)
    if len(mesh_vertices) != len(ref_vertices) or faces != ref_faces:
        sys.exit(f'{args.reference}: not the vertex reference of {args.mesh} (different vertices or faces)')
    sums = {}
    for face in faces:
        for k in range(1, len(face) - 1):
            corners = (face[0], face[k], face[k + 1])
            p = [(mesh_vertices[i]['x'], mesh_vertices[i]['y'], mesh_vertices[i]['z']) for i in corners]
            e1 = [p[1][j] - p[0][j] for j in range(3)]
            e2 = [p[2][j] - p[0][j] for j in range(3)]
            n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
            double_area = math.sqrt(sum(c * c for c in n))
            if double_area == 0:
                continue
            centroid = [sum(q[j] for q in p) / 3 for j in range(3)]
            if any(inside(e, centroid) for e in excluded):
                continue
            facing = 'up' if n[1] / double_area > 0.9 else 'down' if n[1] / double_area < -0.9 else 'side'
            for name, box in boxes:
                if inside(box, centroid):
                    s = sums.setdefault((name, facing), [0.0, 0.0, 0.0])
                    s[0] += double_area * sum(luminance(mesh_vertices[i]) for i in corners)
                    s[1] += double_area * sum(luminance(ref_vertices[i]) for i in corners)
                    s[2] += 0.5 * double_area
                    break
    print(f'{"region":<16} {"facing":<6} {"area":>9} {"solve/reference":>16}')
    for (name, facing), (solved, reference, area) in sorted(sums.items()):
        ratio = f'{solved / reference:.4f}' if reference > 0 else 'n/a'
        print(f'{name:<16} {facing:<6} {area:>9.3f} {ratio:>16}')


if __name__ == '__main__':
    main()

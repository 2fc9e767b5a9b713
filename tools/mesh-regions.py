#!/usr/bin/env python3
"""Compares a solved mesh with its vertex reference region by region, by area.

    tools/mesh-regions.py D/mesh.ply REFERENCE --box NAME=x0,x1,y0,y1,z0,z1 ...
                          [--exclude x0,x1,y0,y1,z0,z1 ...]
    tools/mesh-regions.py D/mesh.ply REFERENCE --obj SCENE.obj

D/mesh.ply is what `lhr solve` exported. REFERENCE is what `lhr reference
--at-vertices D/mesh.ply` wrote for it (same vertices and faces), or a
number: the radiance every vertex should have (2 in a furnace of ρ 0.5 and
Le 1). Every triangle whose centroid lies in a box (and in no --exclude box)
counts with its area times the mean of its corners' linear luminance, in
both. Per box and per orientation of the triangle (facing up, down, or
sideways) the script prints solve / reference: the product's error where the
camera does not look, as the pixel norm of `lhr compare` cannot show it
(docs/accuracy.md, "What a table hides"). With --obj, the regions are the
OBJ file's groups instead, each side of a group apart (a triangle belongs to
the polygon it lies in), lowest ratio first. On regions far darker than
the scene's mean (the inside of a closed shelf) the ratio is mostly the
reference's noise: look at its per-vertex standard error (`lhr compare`)
before reading one. Standard library only.
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


def obj_polygons(path):
    """(group and outward normal, points, unit normal, plane offset) of every face of an OBJ file."""
    points, polygons, group = [], [], 'default'
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == 'v':
                points.append(tuple(float(x) for x in words[1:4]))
            elif words[0] in ('g', 'o'):
                group = ' '.join(words[1:]) or 'default'
            elif words[0] == 'f':
                ids = [int(w.split('/')[0]) for w in words[1:]]
                poly = [points[i - 1] if i > 0 else points[i] for i in ids]
                n = [0.0, 0.0, 0.0]
                for k in range(1, len(poly) - 1):
                    c = cross(sub(poly[k], poly[0]), sub(poly[k + 1], poly[0]))
                    n = [n[j] + c[j] for j in range(3)]
                length = math.sqrt(dot(n, n))
                if length == 0:
                    continue
                n = [x / length for x in n]
                side = ','.join(str(round(x)) for x in n) if max(abs(x) for x in n) > 0.999 else 'oblique'
                polygons.append((f'{group} {side}', poly, n, dot(n, poly[0])))
    return polygons


def sub(a, b):
    return [a[j] - b[j] for j in range(3)]


def dot(a, b):
    return sum(a[j] * b[j] for j in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def in_polygon(p, poly, n):
    """Whether p, in the polygon's plane, lies in the (convex or fanned) polygon."""
    axis = max(range(3), key=lambda j: abs(n[j]))
    u, v = [j for j in range(3) if j != axis]

    def side(a, b):
        return (a[u] - p[u]) * (b[v] - p[v]) - (b[u] - p[u]) * (a[v] - p[v])

    for k in range(1, len(poly) - 1):
        s = [side(poly[0], poly[k]), side(poly[k], poly[k + 1]), side(poly[k + 1], poly[0])]
        if all(x >= -1e-12 for x in s) or all(x <= 1e-12 for x in s):
            return True
    return False


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('mesh')
    parser.add_argument('reference')
    parser.add_argument('--box', action='append', default=[], metavar='NAME=x0,x1,y0,y1,z0,z1')
    parser.add_argument('--exclude', action='append', default=[], metavar='x0,x1,y0,y1,z0,z1')
    parser.add_argument('--obj', metavar='SCENE.obj', help='regions: the groups of this OBJ file')
    args = parser.parse_args()
    if not args.box and not args.obj:
        sys.exit('give regions: --box NAME=x0,x1,y0,y1,z0,z1 ... or --obj SCENE.obj')
    polygons = obj_polygons(args.obj) if args.obj else []
    boxes = []
    for b in args.box:
        name, _, coords = b.partition('=')
        boxes.append((name, parse_box(coords)))
    excluded = [parse_box(e) for e in args.exclude]
    mesh_vertices, faces = read_ply(args.mesh)
    try:
        expected = float(args.reference)
        ref_luminance = [expected] * len(mesh_vertices)
    except ValueError:
        ref_vertices, ref_faces = read_ply(args.reference)
        if len(mesh_vertices) != len(ref_vertices) or faces != ref_faces:
            sys.exit(f'{args.reference}: not the vertex reference of {args.mesh} (different vertices or faces)')
        ref_luminance = [luminance(v) for v in ref_vertices]
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
            region = None
            if polygons:
                unit = [c / double_area for c in n]
                for name, poly, normal, offset in polygons:
                    if dot(unit, normal) > 0.999 and abs(dot(normal, centroid) - offset) < 1e-3 and \
                            in_polygon(centroid, poly, normal):
                        region = (name, '')
                        break
                region = region or ('(no group)', facing)
            else:
                region = next(((name, facing) for name, box in boxes if inside(box, centroid)), None)
            if region is None:
                continue
            s = sums.setdefault(region, [0.0, 0.0, 0.0])
            s[0] += double_area * sum(luminance(mesh_vertices[i]) for i in corners)
            s[1] += double_area * sum(ref_luminance[i] for i in corners)
            s[2] += 0.5 * double_area
    rows = sorted(sums.items())
    if polygons:
        rows.sort(key=lambda row: row[1][0] / row[1][1] if row[1][1] > 0 else math.inf)
    width = max([16] + [len(name) for name, _ in sums])
    print(f'{"region":<{width}} {"facing":<6} {"area":>9} {"solve/reference":>16}')
    for (name, facing), (solved, reference, area) in rows:
        ratio = f'{solved / reference:.4f}' if reference > 0 else 'n/a'
        print(f'{name:<{width}} {facing:<6} {area:>9.3f} {ratio:>16}')


if __name__ == '__main__':
    main()

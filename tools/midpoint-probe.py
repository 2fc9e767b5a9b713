#!/usr/bin/env python3
"""How much power a mesh's linear interpolant misses, region by region.

    tools/midpoint-probe.py split D/mesh.ply D/split.ply
    lhr reference SCENE --at-vertices D/split.ply --spp 4096 --out D/split-ref.ply
    tools/midpoint-probe.py compare D/mesh.ply D/split-ref.ply --obj SCENE.obj

    tools/midpoint-probe.py crop D/mesh.ply D/part.ply --obj SCENE.obj --region PREFIX

`crop` keeps the triangles of the OBJ regions whose name starts with PREFIX
(e.g. `dining_table_apron`), with their vertices' values, so that only a
part of a large scene is traced: split and compare D/part.ply instead.

`split` cuts every triangle of an exported mesh into four at its edge
midpoints (positions only), so that the vertex reference can be traced at
the midpoints too. `compare` then integrates each triangle two ways from the
traced radiance: by the quadratic rule (the mean of its three edge midpoints,
"P2", exact for a quadratic field) and as the linear interpolant of its
corners ("P1", what the solver's elements carry when their corner values are
exact). Per region of the OBJ file (each side of a group apart, as
tools/mesh-regions.py names them) it prints P2/P1, above 1 where the field
bends down between the vertices, and the solve's own integral over both.
docs/accuracy.md, "Concave junctions", is what it was written for. Standard
library only.
"""
import argparse
import importlib.util
import math
import os
import struct
import sys

_spec = importlib.util.spec_from_file_location(
    'mesh_regions', os.path.join(os.path.dirname(os.path.abspath(__file__)), 'mesh-regions.py'))
regions = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(regions)


def midpoints(faces, count):
    """Index of each edge's midpoint, numbered after the `count` vertices in face order."""
    index = {}
    for face in faces:
        for k in range(3):
            key = tuple(sorted((face[k], face[(k + 1) % 3])))
            if key not in index:
                index[key] = count + len(index)
    return index


def split(args):
    vertices, faces = regions.read_ply(args.mesh)
    if any(len(f) != 3 for f in faces):
        sys.exit(f'{args.mesh}: only triangles are split')
    points = [(v['x'], v['y'], v['z']) for v in vertices]
    index = midpoints(faces, len(points))
    extra = [None] * len(index)
    for (a, b), i in index.items():
        extra[i - len(points)] = tuple(0.5 * (points[a][j] + points[b][j]) for j in range(3))
    points += extra
    out = []
    for a, b, c in faces:
        ab, bc, ca = (index[tuple(sorted(e))] for e in ((a, b), (b, c), (c, a)))
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    temporary = args.out + '.tmp'
    with open(temporary, 'wb') as f:
        f.write(('ply\nformat binary_little_endian 1.0\n'
                 f'element vertex {len(points)}\nproperty float x\nproperty float y\nproperty float z\n'
                 f'element face {len(out)}\nproperty list uchar int vertex_indices\nend_header\n').encode())
        for p in points:
            f.write(struct.pack('<3f', *p))
        for t in out:
            f.write(struct.pack('<B3i', 3, *t))
    os.replace(temporary, args.out)


def region_of(polygons, p):
    """The OBJ region a triangle lies in (its plane, facing and polygon), or 'unmatched'."""
    n = regions.cross(regions.sub(p[1], p[0]), regions.sub(p[2], p[0]))
    double_area = math.sqrt(regions.dot(n, n))
    if double_area == 0:
        return None, 0.0
    unit = [c / double_area for c in n]
    centroid = [sum(q[j] for q in p) / 3 for j in range(3)]
    for region, poly, normal, offset in polygons:
        if regions.dot(unit, normal) > 0.999 and abs(regions.dot(normal, centroid) - offset) < 1e-3 and \
                regions.in_polygon(centroid, poly, normal):
            return region, double_area
    return 'unmatched', double_area


def crop(args):
    vertices, faces = regions.read_ply(args.mesh)
    polygons = [p for p in regions.obj_polygons(args.obj) if p[0].startswith(args.region)]
    kept = []
    for face in faces:
        p = [(vertices[i]['x'], vertices[i]['y'], vertices[i]['z']) for i in face]
        name, _ = region_of(polygons, p)
        if name not in (None, 'unmatched'):
            kept.append(face)
    if not kept:
        sys.exit(f'{args.mesh}: no triangle lies in a region of {args.obj} starting with {args.region!r}')
    used = sorted({i for face in kept for i in face})
    index = {v: k for k, v in enumerate(used)}
    names = list(vertices[0].keys())
    temporary = args.out + '.tmp'
    with open(temporary, 'wb') as f:
        f.write(('ply\nformat binary_little_endian 1.0\n' + f'element vertex {len(used)}\n' +
                 ''.join(f'property double {n}\n' for n in names) +
                 f'element face {len(kept)}\nproperty list uchar int vertex_indices\nend_header\n').encode())
        for i in used:
            f.write(struct.pack(f'<{len(names)}d', *[float(vertices[i][n]) for n in names]))
        for face in kept:
            f.write(struct.pack('<B3i', 3, *[index[i] for i in face]))
    os.replace(temporary, args.out)


def compare(args):
    vertices, faces = regions.read_ply(args.mesh)
    traced, _ = regions.read_ply(args.reference)
    index = midpoints(faces, len(vertices))
    if len(traced) != len(vertices) + len(index):
        sys.exit(f'{args.reference}: {len(traced)} vertices, not those of `split {args.mesh}`')
    reference = [regions.luminance(v) for v in traced]
    polygons = regions.obj_polygons(args.obj)
    sums = {}
    for face in faces:
        p = [(vertices[i]['x'], vertices[i]['y'], vertices[i]['z']) for i in face]
        name, double_area = region_of(polygons, p)
        if name is None:
            continue
        edges = [index[tuple(sorted((face[k], face[(k + 1) % 3])))] for k in range(3)]
        s = sums.setdefault(name, [0.0, 0.0, 0.0, 0.0])
        s[0] += double_area / 2
        s[1] += double_area * sum(reference[i] for i in face)
        s[2] += double_area * sum(reference[i] for i in edges)
        s[3] += double_area * sum(regions.luminance(vertices[i]) for i in face)
    width = max(len(k) for k in sums)
    print(f'{"region":<{width}} {"area":>9} {"P2/P1":>8} {"solve/P2":>9}')
    for name, (area, p1, p2, solve) in sorted(sums.items(), key=lambda kv: -kv[1][0]):
        if p1 > 0 and p2 > 0:
            print(f'{name:<{width}} {area:>9.3f} {p2 / p1:>8.4f} {solve / p2:>9.4f}')


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    sub = parser.add_subparsers(dest='command', required=True)
    s = sub.add_parser('split', help='cut every triangle into four for the vertex reference')
    s.add_argument('mesh')
    s.add_argument('out')
    c = sub.add_parser('compare', help='P2/P1 and solve/P2 per region')
    c.add_argument('mesh')
    c.add_argument('reference')
    c.add_argument('--obj', required=True)
    k = sub.add_parser('crop', help='keep the triangles of some OBJ regions, with their values')
    k.add_argument('mesh')
    k.add_argument('out')
    k.add_argument('--obj', required=True)
    k.add_argument('--region', required=True, help='keep regions whose name starts with this')
    args = parser.parse_args()
    {'split': split, 'compare': compare, 'crop': crop}[args.command](args)


if __name__ == '__main__':
    main()

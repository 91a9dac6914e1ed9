#!/usr/bin/env python3
"""Writes scenes/examples/meshes/blob_bunny.obj: a bunny-like solid made of four overlapping
closed ellipsoid meshes (body, head, two ears), each an icosphere subdivided twice.

The parts overlap and are not merged: the mesh shape's winding-number test counts a point inside
when it is inside any part, so a scene can use such a "soup" of closed pieces directly.
Run from the repository root: python3 scripts/make_example_mesh.py
"""
import math

def icosphere(levels):
    t = (1 + math.sqrt(5)) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
             (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    norm = lambda v: tuple(c / math.sqrt(sum(x * x for x in v)) for c in v)
    verts = [norm(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}
        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                verts.append(norm(tuple((x + y) / 2 for x, y in zip(verts[a], verts[b]))))
                mid[key] = len(verts) - 1
            return mid[key]
        nxt = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            nxt += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = nxt
    return verts, faces

# (centre, semi-axes, tilt about z in degrees) in a unit roughly 0.2 m tall.
PARTS = [
    ((0.0, 0.06, 0.0), (0.09, 0.065, 0.07), 0),     # body
    ((0.075, 0.125, 0.0), (0.045, 0.04, 0.04), 0),  # head
    ((0.07, 0.18, 0.018), (0.012, 0.045, 0.012), -15),   # ear
    ((0.07, 0.18, -0.018), (0.012, 0.045, 0.012), -15),  # ear
]

def main():
    unit_v, unit_f = icosphere(2)
    lines = ["# blob_bunny: four overlapping ellipsoids; written by scripts/make_example_mesh.py"]
    base = 0
    for (cx, cy, cz), (ax, ay, az), tilt in PARTS:
        c, s = math.cos(math.radians(tilt)), math.sin(math.radians(tilt))
        for x, y, z in unit_v:
            x, y, z = x * ax, y * ay, z * az
            x, y = c * x - s * y, s * x + c * y
            lines.append("v %.5f %.5f %.5f" % (x + cx, y + cy, z + cz))
        lines += ["f %d %d %d" % (a + base + 1, b + base + 1, cc + base + 1) for a, b, cc in unit_f]
        base += len(unit_v)
    with open("scenes/examples/meshes/blob_bunny.obj", "w") as f:
        f.write("\n".join(lines) + "\n")

if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes the shipped payload meshes (config/payloads/meshes/).

Run from anywhere:  python3 config/payloads/generate_meshes.py
The meshes are committed; this script is how they were made and how to remake them.
Every mesh is a single closed, outward-oriented surface (no overlapping parts), so the
inside/outside tests and signed distances of the planner are exact for it.

  t_bar.stl     binary STL  T of 60 mm square tube: stem 0.6 m (along +x, free end at x = 0),
                            crossbar 1.0 m (along y) at the far end. Frame P: origin at the
                            centre of the stem's free end, x along the stem, z across the section.
  long_bar.obj  OBJ         1.4 x 0.10 x 0.06 m box centred on the origin, long axis x.
  arc.ply       ASCII PLY   quarter ring, centre-line radius 0.5 m, 60 mm square section, in the
                            x-y plane, from angle -45 deg to +45 deg about the origin, so the arc's
                            midpoint is at (0.5, 0, 0); frame P origin at the ring centre.
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "meshes")


def extrude(polygon_xy, z0, z1, cap_triangles):
    """Closed prism from a counter-clockwise polygon; cap_triangles index the polygon."""
    n = len(polygon_xy)
    verts = [(x, y, z0) for x, y in polygon_xy] + [(x, y, z1) for x, y in polygon_xy]
    tris = []
    for a, b, c in cap_triangles:
        tris.append((a + n, b + n, c + n))  # top, counter-clockwise seen from +z
        tris.append((a, c, b))              # bottom, reversed
    for i in range(n):
        j = (i + 1) % n
        tris.append((i, j, j + n))
        tris.append((i, j + n, i + n))
    return verts, tris


def t_bar():
    w = 0.06          # tube section
    stem = 0.6        # free end to far face of the crossbar
    half = 0.5        # half crossbar length
    xs = stem - w     # where the crossbar starts
    poly = [(0.0, -w / 2), (xs, -w / 2), (xs, -half), (stem, -half),
            (stem, half), (xs, half), (xs, w / 2), (0.0, w / 2)]
    caps = [(0, 1, 6), (0, 6, 7),          # stem rectangle
            (2, 3, 4), (2, 4, 5)]          # crossbar rectangle (shares edge 1-6 with stem)
    # The stem rectangle's edge 1-6 lies inside the crossbar rectangle's edge 2-5; split the
    # crossbar cap so the cap is a proper triangulation of the T outline (no T-junctions).
    caps = [(0, 1, 6), (0, 6, 7), (2, 3, 1), (1, 3, 4), (1, 4, 6), (6, 4, 5)]
    return extrude(poly, -w / 2, w / 2, caps)


def box(sx, sy, sz):
    poly = [(-sx / 2, -sy / 2), (sx / 2, -sy / 2), (sx / 2, sy / 2), (-sx / 2, sy / 2)]
    return extrude(poly, -sz / 2, sz / 2, [(0, 1, 2), (0, 2, 3)])


def arc(radius=0.5, section=0.06, start=-math.pi / 4, end=math.pi / 4, segments=48):
    r0, r1 = radius - section / 2, radius + section / 2
    z0, z1 = -section / 2, section / 2
    verts, tris = [], []
    # four vertices per station: inner-bottom, outer-bottom, outer-top, inner-top
    for k in range(segments + 1):
        a = start + (end - start) * k / segments
        c, s = math.cos(a), math.sin(a)
        verts += [(r0 * c, r0 * s, z0), (r1 * c, r1 * s, z0), (r1 * c, r1 * s, z1), (r0 * c, r0 * s, z1)]
    for k in range(segments):
        b, n = 4 * k, 4 * (k + 1)
        for f in range(4):
            g = (f + 1) % 4
            # quad (b+f, b+g, n+g, n+f): outward for the ring swept counter-clockwise
            tris.append((b + f, n + g, b + g))
            tris.append((b + f, n + f, n + g))
    last = 4 * segments
    tris += [(0, 1, 2), (0, 2, 3)]                             # start cap, faces -tangent
    tris += [(last, last + 2, last + 1), (last, last + 3, last + 2)]  # end cap
    return verts, tris


def check_closed_and_oriented(verts, tris, name):
    edges = {}
    for t in tris:
        for i in range(3):
            e = (t[i], t[(i + 1) % 3])
            edges[e] = edges.get(e, 0) + 1
    for (a, b), count in edges.items():
        if count != 1 or edges.get((b, a), 0) != 1:
            raise SystemExit(f"{name}: edge {a}-{b} is not shared by exactly two opposite triangles")
    # positive signed volume <=> outward orientation
    vol = 0.0
    for a, b, c in tris:
        ax, ay, az = verts[a]; bx, by, bz = verts[b]; cx, cy, cz = verts[c]
        vol += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    if vol <= 0:
        raise SystemExit(f"{name}: inward-oriented (volume {vol})")
    return vol


def normal(v, t):
    a, b, c = (v[i] for i in t)
    u = [b[i] - a[i] for i in range(3)]
    w = [c[i] - a[i] for i in range(3)]
    n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
    L = math.sqrt(sum(x * x for x in n)) or 1.0
    return [x / L for x in n]


def write_stl(path, verts, tris):
    with open(path, "wb") as f:
        f.write(b"porter payload mesh".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", *normal(verts, t)))
            for i in t:
                f.write(struct.pack("<3f", *verts[i]))
            f.write(struct.pack("<H", 0))


def write_obj(path, verts, tris):
    with open(path, "w") as f:
        f.write("# porter payload mesh\n")
        for v in verts:
            f.write("v %.9g %.9g %.9g\n" % v)
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def write_ply(path, verts, tris):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment porter payload mesh\n")
        f.write(f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write(f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in verts:
            f.write("%.9g %.9g %.9g\n" % v)
        for t in tris:
            f.write("3 %d %d %d\n" % t)


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, (verts, tris), writer, ext in [
        ("t_bar", t_bar(), write_stl, "stl"),
        ("long_bar", box(1.4, 0.10, 0.06), write_obj, "obj"),
        ("arc", arc(), write_ply, "ply"),
    ]:
        vol = check_closed_and_oriented(verts, tris, name)
        path = os.path.join(OUT, f"{name}.{ext}")
        writer(path, verts, tris)
        print(f"{path}: {len(verts)} vertices, {len(tris)} triangles, volume {vol:.6f} m^3")


if __name__ == "__main__":
    main()

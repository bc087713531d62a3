#!/usr/bin/python3
"""Writes closed triangle meshes (binary STL) of the immersed-boundary test bodies.

    scripts/make_body_stl.py cylinder OUT.stl [--diameter 1] [--segments 128] [--length 1]
                             [--center 0 0 0]
    scripts/make_body_stl.py sphere OUT.stl [--diameter 1] [--level 4] [--center 0 0 0]
    scripts/make_body_stl.py tube OUT.stl --diameter 2.5 --inner-diameter 2 [--segments 256] [--length 1]

cylinder: a prism of `segments` sides along z (a 2D fluid's circle; its length
does not matter there), its two end caps fanned from their centres. sphere: an
icosahedron split `level` times, its vertices pushed onto the sphere (20 4^level
triangles). tube: a cylinder with a coaxial bore of `inner-diameter` (an
annular prism: the outer and the bore's surfaces, annular end caps); its bore
holds fluid (the outer wall of a Couette cell). Normals point out of the solid
(into the bore on the bore's surface). Needs only the standard library.
"""
import argparse
import math
import struct

ap = argparse.ArgumentParser()
ap.add_argument("shape", choices=["cylinder", "sphere", "tube"])
ap.add_argument("out")
ap.add_argument("--diameter", type=float, default=1.0)
ap.add_argument("--inner-diameter", type=float, default=0.0)
ap.add_argument("--segments", type=int, default=128)
ap.add_argument("--length", type=float, default=1.0)
ap.add_argument("--level", type=int, default=4)
ap.add_argument("--center", type=float, nargs=3, default=[0.0, 0.0, 0.0])
a = ap.parse_args()
r = 0.5 * a.diameter
c = a.center


def cylinder():
    n, h = a.segments, 0.5 * a.length
    ring = [(c[0] + r * math.cos(2 * math.pi * k / n), c[1] + r * math.sin(2 * math.pi * k / n)) for k in range(n)]
    lo, hi = (c[0], c[1], c[2] - h), (c[0], c[1], c[2] + h)
    tris = []
    for k in range(n):
        (x0, y0), (x1, y1) = ring[k], ring[(k + 1) % n]
        p0, p1 = (x0, y0, c[2] - h), (x1, y1, c[2] - h)
        q0, q1 = (x0, y0, c[2] + h), (x1, y1, c[2] + h)
        tris += [(p0, p1, q1), (p0, q1, q0), (lo, p1, p0), (hi, q0, q1)]
    return tris


def tube():
    n, h, ri = a.segments, 0.5 * a.length, 0.5 * a.inner_diameter
    if not 0 < ri < r:
        raise SystemExit("tube: --inner-diameter must lie between 0 and --diameter")
    def at(rad, k, z):
        t = 2 * math.pi * (k % n) / n
        return (c[0] + rad * math.cos(t), c[1] + rad * math.sin(t), c[2] + z)

    tris = []
    for k in range(n):
        o0, o1, O0, O1 = at(r, k, -h), at(r, k + 1, -h), at(r, k, h), at(r, k + 1, h)
        i0, i1, I0, I1 = at(ri, k, -h), at(ri, k + 1, -h), at(ri, k, h), at(ri, k + 1, h)
        tris += [(o0, o1, O1), (o0, O1, O0)]  # outer surface, normals away from the axis
        tris += [(i0, I1, i1), (i0, I0, I1)]  # the bore's surface, normals towards the axis
        tris += [(i0, o1, o0), (i0, i1, o1)]  # lower cap, normals -z
        tris += [(I0, O0, O1), (I0, O1, I1)]  # upper cap, normals +z
    return tris


def sphere():
    t = (1 + math.sqrt(5)) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    unit = lambda p: tuple(x / math.sqrt(sum(y * y for y in p)) for x in p)
    v = [unit(p) for p in v]
    for _ in range(a.level):
        mids, g = {}, []

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in mids:
                v.append(unit(tuple((v[i][d] + v[j][d]) / 2 for d in range(3))))
                mids[key] = len(v) - 1
            return mids[key]

        for i, j, k in f:
            ij, jk, ki = mid(i, j), mid(j, k), mid(k, i)
            g += [(i, ij, ki), (j, jk, ij), (k, ki, jk), (ij, jk, ki)]
        f = g
    p = [tuple(c[d] + r * q[d] for d in range(3)) for q in v]
    return [(p[i], p[j], p[k]) for i, j, k in f]


tris = {"cylinder": cylinder, "sphere": sphere, "tube": tube}[a.shape]()
with open(a.out, "wb") as out:
    out.write(b"coflow immersed-boundary body".ljust(80, b" "))
    out.write(struct.pack("<I", len(tris)))
    for t in tris:
        out.write(struct.pack("<3f", 0.0, 0.0, 0.0))
        for p in t:
            out.write(struct.pack("<3f", *p))
        out.write(b"\0\0")
print(f"{a.out}: {len(tris)} triangles")

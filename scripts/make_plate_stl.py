#!/usr/bin/python3
"""Writes a plate as a closed triangle mesh (binary STL) for the granular-jet case
(seed 003 §5.3: a 0.1 m x 0.1 m plate of about 105 000 triangles).

    scripts/make_plate_stl.py OUT.stl [--size 0.1] [--thickness 0.002] [--cells 161]
                              [--center 0.1 0.05 0.1] [--normal y] [--tilt 0]

The plate is a box of size x size x thickness whose two large faces are split
into cells x cells squares of two triangles each and whose four sides into
cells x 1 squares: 4 cells^2 + 8 cells triangles (104 972 for 161). --normal
names the axis of the plate's normal; --tilt rotates the plate by that many
degrees about the first of the other two axes. Needs only the standard library.
"""
import argparse
import math
import os
import struct

ap = argparse.ArgumentParser()
ap.add_argument("out")
ap.add_argument("--size", type=float, default=0.1)
ap.add_argument("--thickness", type=float, default=0.002)
ap.add_argument("--cells", type=int, default=161)
ap.add_argument("--center", type=float, nargs=3, default=[0.1, 0.05, 0.1])
ap.add_argument("--normal", choices=["x", "y", "z"], default="y")
ap.add_argument("--tilt", type=float, default=0.0)
a = ap.parse_args()

n = a.cells
h, t = 0.5 * a.size, 0.5 * a.thickness
tris = []


def quad(p, q, r, s):  # counter-clockwise seen from outside
    tris.append((p, q, r))
    tris.append((p, r, s))


def grid(u):
    return -h + a.size * u / n


# local frame: plate in (u, v), normal w; faces w = +t and w = -t, sides at u, v = +-h
for i in range(n):
    for j in range(n):
        u0, u1, v0, v1 = grid(i), grid(i + 1), grid(j), grid(j + 1)
        quad((u0, v0, t), (u1, v0, t), (u1, v1, t), (u0, v1, t))
        quad((u0, v0, -t), (u0, v1, -t), (u1, v1, -t), (u1, v0, -t))
for i in range(n):
    s0, s1 = grid(i), grid(i + 1)
    quad((s0, -h, -t), (s1, -h, -t), (s1, -h, t), (s0, -h, t))
    quad((s1, h, -t), (s0, h, -t), (s0, h, t), (s1, h, t))
    quad((-h, s1, -t), (-h, s0, -t), (-h, s0, t), (-h, s1, t))
    quad((h, s0, -t), (h, s1, -t), (h, s1, t), (h, s0, t))

w_axis = "xyz".index(a.normal)
u_axis, v_axis = [k for k in range(3) if k != w_axis]
# (u, v, w) -> (x, z, y) for --normal y is a mirror: each triangle's order is
# reversed there, so that the triangles stay counter-clockwise seen from
# outside (outward normals; coflow validate refuses a mesh facing inward).
if (u_axis, v_axis, w_axis) == (0, 2, 1):
    tris = [(p, r, q) for p, q, r in tris]
c, s = math.cos(math.radians(a.tilt)), math.sin(math.radians(a.tilt))


def place(p):
    u, v, w = p
    v, w = c * v - s * w, s * v + c * w  # tilt about the u axis
    x = [0.0, 0.0, 0.0]
    x[u_axis], x[v_axis], x[w_axis] = u, v, w
    return [x[k] + a.center[k] for k in range(3)]


os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
with open(a.out, "wb") as f:
    f.write(b"coflow plate".ljust(80, b" "))
    f.write(struct.pack("<I", len(tris)))
    for tri in tris:
        p = [place(q) for q in tri]
        e1 = [p[1][k] - p[0][k] for k in range(3)]
        e2 = [p[2][k] - p[0][k] for k in range(3)]
        nrm = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        ln = math.sqrt(sum(x * x for x in nrm)) or 1.0
        f.write(struct.pack("<12fH", *[x / ln for x in nrm], *p[0], *p[1], *p[2], 0))
print(f"{a.out}: {len(tris)} triangles")

#!/usr/bin/python3
"""Writes the inlet tables of the backward-facing step of Driver & Seegmiller
(1985), configs/validation/fv_ke_backward_step.yaml: the flow entering at the
step's edge (x = 0), in units of the step height H and the reference speed U.

    scripts/make_bfs_inlet.py DIR [--delta 1.5] [--utau 0.0374] [--intensity 0.01] [--rows 400]

DIR/bfs_inlet_velocity.csv: rows `y, factor` on the face's value U (y in H):
0 below the step's edge (y < 1: the step's face, no flow), a 1/7-power
boundary layer of thickness delta on the floor upstream (y = 1) and on the
top wall (y = 9), 1 between them. DIR/bfs_inlet_turbulence.csv: rows `y, k,
epsilon`: in the boundary layers k = u_tau^2 / sqrt(C_mu) (1 - d / delta)
plus the free stream's k_inf = 3/2 (I U)^2, d the distance to the wall;
epsilon = C_mu^(3/4) k^(3/2) / l with Escudier's mixing length l = min(kappa
d, 0.09 delta) (0.09 delta in the free stream); below the step's edge the
free stream's k and epsilon (nothing enters there). delta = 1.5 H is Driver & Seegmiller's 1.9 cm at
x = -4 H (H = 1.27 cm); u_tau = 0.0374 U from their Cf of about 0.0028
upstream (Cf = 2 (u_tau / U)^2). Needs only the standard library.
"""
import argparse
import math
import os

ap = argparse.ArgumentParser()
ap.add_argument("dir")
ap.add_argument("--delta", type=float, default=1.5)
ap.add_argument("--utau", type=float, default=0.0374)
ap.add_argument("--intensity", type=float, default=0.01)
ap.add_argument("--rows", type=int, default=400)
a = ap.parse_args()

C_MU, KAPPA, TOP = 0.09, 0.41, 9.0
k_inf = 1.5 * (a.intensity * 1.0) ** 2
d_min = 1.0 / 64  # the first row off a wall (the tables are linear between rows)


def at(y):
    """u factor, k, epsilon at height y (in H)."""
    if y < 1.0:
        l = 0.09 * a.delta
        return 0.0, k_inf, C_MU ** 0.75 * k_inf ** 1.5 / l
    d = max(min(y - 1.0, TOP - y), d_min)
    if d >= a.delta:
        u, k = 1.0, k_inf
    else:
        u = (d / a.delta) ** (1.0 / 7.0)
        k = a.utau ** 2 / math.sqrt(C_MU) * (1.0 - d / a.delta) + k_inf
    l = min(KAPPA * d, 0.09 * a.delta)
    return u, k, C_MU ** 0.75 * k ** 1.5 / l


ys = sorted(set([0.0, 1.0 - 1e-9] + [1.0 + (TOP - 1.0) * i / a.rows for i in range(a.rows + 1)]))
with open(os.path.join(a.dir, "bfs_inlet_velocity.csv"), "w") as f:
    f.write("# Written by scripts/make_bfs_inlet.py: the backward-facing step's inlet profile, y (m), factor\n")
    for y in ys:
        f.write(f"{y:.9g}, {at(y)[0]:.9g}\n")
with open(os.path.join(a.dir, "bfs_inlet_turbulence.csv"), "w") as f:
    f.write("# Written by scripts/make_bfs_inlet.py: the backward-facing step's inlet k and epsilon\n")
    f.write("y, k, epsilon\n")
    for y in ys:
        _, k, e = at(y)
        f.write(f"{y:.9g}, {k:.9g}, {e:.9g}\n")

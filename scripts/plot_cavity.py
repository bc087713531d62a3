"""Lid-driven cavity on fv: u along the vertical centre line and v along the
horizontal one, against Ghia, Ghia & Shin 1982 (Tables I and II), for one or
more finished runs (each of Re 100 or 1000).

Usage: plot_cavity.py OUT_PNG RUN_DIR [RUN_DIR ...]
  RUN_DIR   a finished run of configs/validation/fv_cavity_re*.yaml or
            configs/cases/fv_cavity_re*_256.yaml
"""
import glob
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import yaml

# Ghia, Ghia & Shin 1982, Table I (u at x = 0.5) and Table II (v at y = 0.5);
# the same numbers as tests/validation/fv/checks.cpp (sources in
# tests/validation/references.csv).
Y = [0.0, 0.0547, 0.0625, 0.0703, 0.1016, 0.1719, 0.2813, 0.4531, 0.5, 0.6172, 0.7344, 0.8516, 0.9531, 0.9609,
     0.9688, 0.9766, 1.0]
U = {100: [0.0, -0.03717, -0.04192, -0.04775, -0.06434, -0.10150, -0.15662, -0.21090, -0.20581, -0.13641, 0.00332,
           0.23151, 0.68717, 0.73722, 0.78871, 0.84123, 1.0],
     1000: [0.0, -0.18109, -0.20196, -0.22220, -0.29730, -0.38289, -0.27805, -0.10648, -0.06080, 0.05702, 0.18719,
            0.33304, 0.46604, 0.51117, 0.57492, 0.65928, 1.0]}
X = [0.0, 0.0625, 0.0703, 0.0781, 0.0938, 0.1563, 0.2266, 0.2344, 0.5, 0.8047, 0.8594, 0.9063, 0.9453, 0.9531,
     0.9609, 0.9688, 1.0]
V = {100: [0.0, 0.09233, 0.10091, 0.10890, 0.12317, 0.16077, 0.17507, 0.17527, 0.05454, -0.24533, -0.22445,
           -0.16914, -0.10313, -0.08864, -0.07391, -0.05906, 0.0],
     1000: [0.0, 0.27485, 0.29012, 0.30353, 0.32627, 0.37095, 0.33075, 0.32235, 0.02526, -0.31966, -0.42665,
            -0.51550, -0.39188, -0.33714, -0.27669, -0.21388, 0.0]}

out = sys.argv[1]
fig, (au, av) = plt.subplots(1, 2, figsize=(11, 4.6))
for run in sys.argv[2:]:
    cfg = yaml.safe_load(open(f"{run}/config.yaml"))
    re = round(1.0 / cfg["fluid"]["viscosity"])
    snap = sorted(glob.glob(f"{run}/fluid/step_*.h5"))[-1]
    u = h5py.File(snap, "r")["velocity"][0]  # [ny][nx][3]
    ny, nx, _ = u.shape
    c = (np.arange(nx) + 0.5) / nx
    ucl = np.concatenate([[0.0], 0.5 * (u[:, nx // 2 - 1, 0] + u[:, nx // 2, 0]), [1.0]])
    vcl = np.concatenate([[0.0], 0.5 * (u[ny // 2 - 1, :, 1] + u[ny // 2, :, 1]), [0.0]])
    s = np.concatenate([[0.0], c, [1.0]])
    au.plot(ucl, s, label=f"fv {nx}$^2$, Re {re}")
    av.plot(s, vcl, label=f"fv {nx}$^2$, Re {re}")
for re in sorted({round(1.0 / yaml.safe_load(open(f"{r}/config.yaml"))["fluid"]["viscosity"]) for r in sys.argv[2:]}):
    au.plot(U[re], Y, "ko" if re == 100 else "ks", mfc="none", label=f"Ghia et al. 1982, Re {re}")
    av.plot(X, V[re], "ko" if re == 100 else "ks", mfc="none", label=f"Ghia et al. 1982, Re {re}")
au.set_xlabel("u / U at x = L/2")
au.set_ylabel("y / L")
av.set_xlabel("x / L")
av.set_ylabel("v / U at y = L/2")
au.legend(fontsize=8)
av.legend(fontsize=8)
fig.suptitle("Lid-driven cavity, finite volumes (fv)")
fig.tight_layout()
fig.savefig(out, dpi=110)
print(f"wrote {out}")

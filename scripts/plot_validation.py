#!/usr/bin/python3
"""Plots of the validation cases for docs/validation.md.

Run the validation tests first (scripts/test -L validation), then
    scripts/plot_validation.py [build/tests] [docs/img]
Uses Debian's python3 with h5py, numpy and matplotlib.
"""
import csv
import glob
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

runs = sys.argv[1] if len(sys.argv) > 1 else "build/tests"
out = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
os.makedirs(out, exist_ok=True)


def last_snapshot(run):
    return h5py.File(sorted(glob.glob(f"{run}/fluid/step_*.h5"))[-1], "r")


def metrics(case):
    m = {}
    with open(f"{runs}/val-{case}/metrics.txt") as f:
        for line in f:
            k, v = line.strip().split("=")
            m[k] = float(v)
    return m


# 1. Poiseuille profiles at 32 cells across.
fig, ax = plt.subplots(figsize=(5, 4))
for case, label, G in [("lbm_poiseuille_2d_force", "body force", 1.5625e-3),
                       ("lbm_poiseuille_2d_pressure", "pressure (Zou-He)", 9.84375e-5 / 63e-3)]:
    with last_snapshot(f"{runs}/val-{case}/run") as f:
        u = f["velocity"][0, :, :, 0]
    ny = u.shape[0]
    H, mu = 0.032, 1e-3
    y = (np.arange(ny) + 0.5) * H / ny
    ax.plot(u.mean(axis=1) * 1e3, y * 1e3, "o", ms=3, label=f"lbm, {label}")
yy = np.linspace(0, 0.032, 200)
ax.plot(1.5625e-3 * yy * (0.032 - yy) / 2e-3 * 1e3, yy * 1e3, "k-", lw=1, label="analytic")
ax.set_xlabel("u (mm/s)")
ax.set_ylabel("y (mm)")
ax.set_title("Plane Poiseuille flow, 32 cells, tau = 0.8")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(f"{out}/lbm_poiseuille_profiles.png", dpi=110)

# 2. Convergence.
fig, ax = plt.subplots(figsize=(5, 4))
for case, label, ns in [("lbm_poiseuille_2d_force_order", "2D, body force", [16, 32, 64]),
                        ("lbm_poiseuille_2d_pressure_order", "2D, pressure", [16, 32, 64]),
                        ("lbm_duct_3d_force_order", "3D duct, body force", [8, 16, 32])]:
    m = metrics(case)
    e = [m["l2_error_1"], m["l2_error_2"], m["l2_error_3"]]
    ax.loglog(ns, e, "o-", label=f"{label} (order {m['order_12']:.2f}, {m['order_23']:.2f})")
n = np.array([8, 64])
ax.loglog(n, 0.5 * (n / 8.0) ** -2, "k--", lw=1, label="slope 2")
ax.set_xlabel("cells across")
ax.set_ylabel("relative L2 error")
ax.set_title("Observed order of convergence")
ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(f"{out}/lbm_convergence.png", dpi=110)

# 3. Taylor-Green decay.
rows = list(csv.DictReader(open(f"{runs}/val-lbm_taylor_green/run/series/fluid.csv")))
t = np.array([float(r["time"]) for r in rows])
E = np.array([float(r["kinetic_energy"]) for r in rows])
k = 2 * math.pi / 0.064
fig, ax = plt.subplots(figsize=(5, 4))
ax.semilogy(t, E / E[0], "o", ms=3, label="lbm")
ax.semilogy(t, np.exp(-2 * 1e-6 * 2 * k * k * t), "k-", lw=1, label="analytic exp(-2 nu k^2 t)")
ax.set_xlabel("t (s)")
ax.set_ylabel("E / E(0)")
ax.set_title(f"Taylor-Green vortex, 64^2: rate error {metrics('lbm_taylor_green')['decay_rate_error']:.1e}")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(f"{out}/lbm_taylor_green.png", dpi=110)

# 4. Large pressure drop: centre-line velocity along the channel.
fig, ax = plt.subplots(figsize=(6, 4))
for form in ["standard", "incompressible"]:
    with last_snapshot(f"{runs}/val-lbm_pressure_large_drop/{form}") as f:
        u = f["velocity"][0, :, :, 0]
    ax.plot(np.arange(u.shape[1]), (u[7, :] + u[8, :]) / 2 * 1e3, label=form)
G = 12.0 / (127 * 1e-3)
H = 0.016
ax.axhline(G * (H / 2) ** 2 / (2 * 0.1) * 1e3, color="k", lw=1, label="analytic (incompressible)")
ax.set_xlabel("x (cells)")
ax.set_ylabel("centre-line u (mm/s)")
m = metrics("lbm_pressure_large_drop")
ax.set_title(f"dp = 0.1 rho c_s^2: L2 error standard {m['l2_error_standard']:.3f}, "
             f"incompressible {m['l2_error_incompressible']:.3f}", fontsize=9)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(f"{out}/lbm_large_pressure_drop.png", dpi=110)
print(f"plots written to {out}/")

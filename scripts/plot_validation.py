#!/usr/bin/python3
"""Plots of the validation cases for docs/validation.md.

Run the validation tests first, keeping their snapshots (a passing test
removes them otherwise): COFLOW_KEEP_TEST_OUTPUT=1 scripts/test -L validation; then
    scripts/plot_validation.py [build/tests] [docs/img] [out/cases]
The third directory, when it exists, holds runs of the full-size settling-sphere
configs, each in a folder named after the case (e1 ... e4):
    coflow run configs/cases/settling_sphere_e1.yaml --set run.output.dir=out/cases/e1
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


def series_lines(path):
    """The lines of a coflow series file without its units line ('# s,kg,...')."""
    return [line for line in open(path) if not line.startswith("#")]


runs = sys.argv[1] if len(sys.argv) > 1 else "build/tests"
out = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
cases = sys.argv[3] if len(sys.argv) > 3 else "out/cases"
os.makedirs(out, exist_ok=True)


def last_snapshot(run):
    return h5py.File(sorted(glob.glob(f"{run}/fluid/step_*.h5"))[-1], "r")


def metrics(case):
    m = {}
    with open(f"{runs}/val-{case}/metrics.txt") as f:
        for line in f:
            k, v = line.strip().split("=")
            try:
                m[k] = float(v)
            except ValueError:  # labels such as case=E2
                m[k] = v
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
rows = list(csv.DictReader(series_lines(f"{runs}/val-lbm_taylor_green/run/series/fluid.csv")))
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

# 5. Settling sphere, ten Cate et al. (2002) case E2.
run = f"{runs}/val-psm_settling_sphere_e2/run"
if os.path.exists(f"{run}/series/particles.csv"):
    rows = list(csv.DictReader(series_lines(f"{run}/series/particles.csv")))
    m = 1120.0 * math.pi * 0.015 ** 3 / 6.0
    t = [float(r["time"]) for r in rows]
    v = [-float(r["momentum_z"]) / m for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(t, v, label="coflow: lbm + psm + dem, d = 12 cells")
    ax.axhline(0.060, color="k", lw=1, ls="--", label="ten Cate et al. 2002, terminal (E2)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("settling speed (m/s)")
    mm = metrics("psm_settling_sphere_e2")
    ax.set_title(f"settling sphere E2: terminal {mm['terminal_velocity']:.4f} m/s "
                 f"({mm['velocity_error']:.1%} from the experiment)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{out}/psm_settling_e2.png", dpi=110)

# 5b. Settling sphere, all four cases of ten Cate et al. (2002), when run.
ten_cate = {"e1": 0.038, "e2": 0.060, "e3": 0.091, "e4": 0.128}  # ten Cate et al. 2002, Table 1
runs_e = {c: f"{cases}/{c}" for c in ten_cate if os.path.exists(f"{cases}/{c}/series/particles.csv")}
if "e2" not in runs_e and os.path.exists(f"{runs}/val-psm_settling_sphere_e2/run/series/particles.csv"):
    runs_e["e2"] = f"{runs}/val-psm_settling_sphere_e2/run"
if len(runs_e) > 1:
    m = 1120.0 * math.pi * 0.015 ** 3 / 6.0
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, (c, run) in enumerate(sorted(runs_e.items())):
        rows = list(csv.DictReader(series_lines(f"{run}/series/particles.csv")))
        ax.plot([float(r["time"]) for r in rows], [-float(r["momentum_z"]) / m for r in rows], color=f"C{k}",
                label=f"{c.upper()} coflow")
        ax.axhline(ten_cate[c], color=f"C{k}", lw=0.8, ls="--")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("settling speed (m/s)")
    ax.set_title("ten Cate et al. 2002 (dashed: measured terminal velocities), d = 12 cells", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{out}/psm_settling_all.png", dpi=110)

# 6. Rotating sphere: torque against Stokes.
run = f"{runs}/val-psm_rotating_sphere/run"
if os.path.exists(f"{run}/series/immersed.csv"):
    im = list(csv.DictReader(series_lines(f"{run}/series/immersed.csv")))
    pa = {round(float(r["time"]), 9): r for r in csv.DictReader(series_lines(f"{run}/series/particles.csv"))}
    a, mu, rho_p = 0.008, 0.1, 50000.0
    I = 0.4 * rho_p * 4.0 / 3.0 * math.pi * a ** 3 * a * a
    t, ratio = [], []
    for r in im:
        key = round(float(r["time"]), 9)
        if key not in pa:
            continue
        omega = math.sqrt(2.0 * float(pa[key]["rotational_energy"]) / I)
        t.append(float(r["time"]))
        ratio.append(abs(float(r["torque_z"])) / (8 * math.pi * mu * a ** 3 * omega))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(t, ratio, "o-", ms=3, label="coflow, d = 16 cells")
    ax.axhline(1.0, color="k", lw=1, ls="--", label="Stokes 8 pi mu a^3 Omega")
    ax.axvline(2 * a * a / 1e-4, color="gray", lw=0.8, ls=":", label="2 a^2 / nu (spin-up)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("torque / Stokes torque")
    ax.set_ylim(0, 1.6)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{out}/psm_rotating_sphere.png", dpi=110)

print(f"plots written to {out}/")

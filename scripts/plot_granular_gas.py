#!/usr/bin/python3
"""Granular-gas plots (seed 003 §5.2) for docs/validation.md.

    scripts/plot_granular_gas.py MONO_RUN BIDISPERSE_RUN [OUT_DIR]
MONO_RUN: a run of configs/validation/dpm_granular_gas.yaml (collision-angle and
relative-speed PDFs against eqs 5.7-5.8); BIDISPERSE_RUN: a run of
configs/validation/dpm_granular_gas_bidisperse.yaml (energy ratios k_p/k_m and
k_q/k_m against eqs 5.18-5.19). OUT_DIR defaults to docs/img. The ctest runs
leave them in build/tests/val-dpm_granular_gas*/run when run with
COFLOW_KEEP_TEST_OUTPUT=1 (a passing test removes its snapshots). Uses Debian's python3 with
h5py, numpy and matplotlib.
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

mono, bi = sys.argv[1], sys.argv[2]
out = sys.argv[3] if len(sys.argv) > 3 else "docs/img"
os.makedirs(out, exist_ok=True)

# Mono: PDFs of the collision angle (from the line of centres) and relative speed.
rows = list(csv.DictReader(open(f"{mono}/events/collisions.csv")))
angle = np.radians([float(r["angle"]) for r in rows])
speed = np.array([float(r["relative_speed"]) for r in rows])
first = sorted(glob.glob(f"{mono}/particles/step_*.h5"))[0]
v = h5py.File(first, "r")["velocity"][:]
T = (v - v.mean(axis=0)).var(axis=0).mean()
fig, ax = plt.subplots(1, 2, figsize=(10, 4))
ax[0].hist(angle, bins=30, range=(0, math.pi / 2), density=True, alpha=0.6, label=f"dpm ({len(angle)} collisions)")
phi = np.linspace(0, math.pi / 2, 200)
ax[0].plot(phi, np.sin(2 * phi), "k-", label="eq. 5.7: sin(2 phi)")
ax[0].set_xlabel("collision angle phi from the line of centres (rad)")
ax[0].set_ylabel("pdf")
ax[0].legend()
ax[1].hist(speed, bins=40, density=True, alpha=0.6, label="dpm")
g = np.linspace(0, speed.max(), 200)
ax[1].plot(g, g**3 / (8 * T**2) * np.exp(-g**2 / (4 * T)), "k-", label=f"eq. 5.8, T = {T:.4f} m^2/s^2")
ax[1].set_xlabel("relative speed at contact (m/s)")
ax[1].legend()
fig.suptitle("monodisperse granular gas, 500 particles, alpha = 0.001")
fig.tight_layout()
fig.savefig(f"{out}/dpm_granular_gas_pdfs.png", dpi=110)

# Bidisperse: energy ratios over time.
snaps = sorted(glob.glob(f"{bi}/particles/step_*.h5"))
times, rp, rq = [], [], []
for s in snaps:
    f = h5py.File(s, "r")
    sp = f["species"][:]
    vel = f["velocity"][:]
    r = f["radius"][:]
    m = r**3  # same density: m ~ r^3
    k = {}
    n = {}
    mass = {}
    for c in (0, 1):
        sel = sp == c
        vv = vel[sel] - vel[sel].mean(axis=0)
        k[c] = 0.5 * (vv**2).sum(axis=1).mean()
        n[c] = sel.sum()
        mass[c] = m[sel][0]
    km = (n[0] * mass[0] * k[0] + n[1] * mass[1] * k[1]) / (n[0] * mass[0] + n[1] * mass[1])
    small = 0 if mass[0] < mass[1] else 1
    times.append(f.attrs["time"])
    rp.append(k[small] / km)
    rq.append(k[1 - small] / km)
    pred_p = (n[0] * mass[0] + n[1] * mass[1]) / (mass[small] * (n[0] + n[1]))
    pred_q = (n[0] * mass[0] + n[1] * mass[1]) / (mass[1 - small] * (n[0] + n[1]))
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(times, rp, "o-", label="k_p / k_m (342 um)")
ax.plot(times, rq, "s-", label="k_q / k_m (684 um)")
ax.axhline(pred_p, color="C0", ls="--", label=f"eq. 5.18: {pred_p:.3f}")
ax.axhline(pred_q, color="C1", ls="--", label=f"eq. 5.19: {pred_q:.3f}")
ax.set_xlabel("time (s)")
ax.set_ylabel("specific kinetic energy / mixture's")
ax.set_title("bidisperse granular gas: approach to equipartition")
ax.legend()
fig.tight_layout()
fig.savefig(f"{out}/dpm_granular_gas_energy.png", dpi=110)
print(f"wrote {out}/dpm_granular_gas_pdfs.png and {out}/dpm_granular_gas_energy.png")

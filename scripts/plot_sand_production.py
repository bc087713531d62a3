#!/usr/bin/python3
"""Plots of a sand-production run (configs/sand_production.yaml).

    scripts/plot_sand_production.py [RUN_DIR] [OUT_DIR]
RUN_DIR defaults to out/sand-production, OUT_DIR to docs/img. Writes
sand_production_history.png (cumulative broken bonds and produced grain mass vs
time) and sand_production_frames.png (mid-plane fluid speed and solid fraction
at four times). Uses Debian's python3 with h5py, numpy and matplotlib.
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


run = sys.argv[1] if len(sys.argv) > 1 else "out/sand-production"
out = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
os.makedirs(out, exist_ok=True)

# Grain mass from the resolved configuration (the sand species).
density = diameter = None
with open(f"{run}/config.yaml") as f:
    lines = f.read().splitlines()
for i, line in enumerate(lines):
    if line.strip().startswith("sand:"):
        for follow in lines[i + 1:i + 6]:
            if "density:" in follow:
                density = float(follow.split(":")[1])
            if "diameter:" in follow:
                diameter = float(follow.split(":")[1])
        break
grain = density * math.pi * diameter ** 3 / 6.0

rows = list(csv.DictReader(series_lines(f"{run}/series/particles.csv")))
t = np.array([float(r["time"]) for r in rows])
count = np.array([float(r["count"]) for r in rows])
broken = np.array([float(r["broken_bonds"]) for r in rows])  # cumulative in the series
produced = (count[0] - count) * grain * 1e3  # g

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(t, broken, color="C3", label="broken bonds")
ax.set_xlabel("time (s)")
ax.set_ylabel("broken bonds (cumulative)", color="C3")
ax2 = ax.twinx()
ax2.plot(t, produced, color="C0", label="produced sand")
ax2.set_ylabel("produced sand (g)", color="C0")
ax.set_title(f"sand production: {int(count[0] - count[-1])} grains out, {int(broken[-1])} bonds broken",
             fontsize=9)
fig.tight_layout()
fig.savefig(f"{out}/sand_production_history.png", dpi=110)

snaps = sorted(glob.glob(f"{run}/fluid/step_*.h5"))
picks = [snaps[int(round(k * (len(snaps) - 1) / 3))] for k in range(4)] if len(snaps) >= 4 else snaps
fig, axes = plt.subplots(len(picks), 1, figsize=(6, 1.9 * len(picks)), squeeze=False)
for ax, path in zip(axes[:, 0], picks):
    with h5py.File(path, "r") as f:
        u = f["velocity"][...]
        phi = f["solid_fraction"][...]
        time = float(f.attrs["time"])
    k = u.shape[0] // 2
    speed = np.linalg.norm(u[k], axis=-1) * 1e3
    im = ax.imshow(speed, origin="lower", cmap="viridis", aspect="equal")
    ax.contour(phi[k], levels=[0.5], colors="w", linewidths=0.4)
    ax.set_title(f"t = {time:.3f} s: |u| (mm/s) in the mid-plane, grains outlined", fontsize=8)
    ax.set_xticks([])
    ax.set_yticks([])
    fig.colorbar(im, ax=ax, fraction=0.02)
fig.tight_layout()
fig.savefig(f"{out}/sand_production_frames.png", dpi=110)
print(f"plots written to {out}/")

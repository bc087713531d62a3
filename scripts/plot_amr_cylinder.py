"""The cylinder at Re 100 on fv's adaptive grid (configs/cases/ibm_cylinder_re100_amr.yaml):
the vorticity behind the cylinder at the end on the composite grid, with
every patch's outline coloured by its level; the lift coefficient over the
last 60 D/U against the same grid refined everywhere (when given); the cells
over time against the finest grid's.

Usage: plot_amr_cylinder.py OUT_PNG AMR_RUN [FINE_RUN]
  AMR_RUN, FINE_RUN: run directories (coflow run ... --set run.output.dir=DIR)
"""
import glob
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle, Rectangle

PATCH = 4  # cells per patch edge (the case's refinement.patch)
DEPTH, DIAMETER, SPEED = 0.1, 1.0, 1.0  # m, m, m/s (rho = 1)


def series(run, name):
    return np.genfromtxt(f"{run}/series/{name}.csv", delimiter=",", names=True, skip_header=0)[1:]


def composite(run):
    path = sorted(glob.glob(f"{run}/fluid/step_*_levels.h5"))[-1]
    parts = {k: [] for k in ("x", "y", "h", "omega", "level")}
    with h5py.File(path, "r") as f:
        for name in sorted(k for k in f if k.endswith("_nodes")):
            p = name[: -len("nodes")]
            nodes = f[name][:].reshape(-1, 4, 3)
            parts["x"].append(nodes[:, :, 0].mean(axis=1))
            parts["y"].append(nodes[:, :, 1].mean(axis=1))
            parts["h"].append(nodes[:, :, 0].max(axis=1) - nodes[:, :, 0].min(axis=1))
            parts["omega"].append(f[p + "vorticity"][:, 0])
            parts["level"].append(f[p + "level"][:, 0])
    return {k: np.concatenate(v) for k, v in parts.items()}


out, amr = sys.argv[1], sys.argv[2]
fine = sys.argv[3] if len(sys.argv) > 3 else None
snap = composite(amr)
window = (snap["x"] > -4) & (snap["x"] < 16) & (np.abs(snap["y"]) < 5)
fig = plt.figure(figsize=(13, 7.5))
ax = fig.add_subplot(2, 1, 1)
squares = [Rectangle((x - h / 2, y - h / 2), h, h) for x, y, h in zip(snap["x"][window], snap["y"][window], snap["h"][window])]
pc = PatchCollection(squares, cmap="magma", linewidths=0)
pc.set_array(np.minimum(snap["omega"][window], 3.0))
ax.add_collection(pc)
fig.colorbar(pc, ax=ax, label="|vorticity| (1/s, clipped at 3)")
colours = {0: "white", 1: "cyan", 2: "lime"}
seen = set()
for x, y, h, level in zip(snap["x"][window], snap["y"][window], snap["h"][window], snap["level"][window].astype(int)):
    size = PATCH * h
    key = (level, int(np.floor((x + 15) / size)), int(np.floor((y + 16) / size)))
    if key not in seen:
        seen.add(key)
        ax.add_patch(Rectangle((key[1] * size - 15, key[2] * size - 16), size, size, fill=False, lw=0.4, ec=colours[level]))
ax.add_patch(Circle((0, 0.03), 0.5, fill=False, ec="w", lw=1))
ax.set_xlim(-4, 16)
ax.set_ylim(-5, 5)
ax.set_aspect("equal")
ax.set_title("Re 100, t = 200 D/U: |vorticity| on 3 levels (patch outlines: white 0, cyan 1, lime 2)")
al = fig.add_subplot(2, 2, 3)
for run, label in ((amr, "adaptive"), (fine, "refined everywhere")):
    if run is None:
        continue
    s = series(run, "immersed")
    keep = s["time"] >= s["time"][-1] - 60
    al.plot(s["time"][keep], 2 * s["cylinder_fy"][keep] / (DEPTH * DIAMETER * SPEED**2), label=label, lw=0.8)
al.set_xlabel("t (D/U)")
al.set_ylabel("lift coefficient")
al.legend(loc="upper right")
ac = fig.add_subplot(2, 2, 4)
f = series(amr, "fluid")
ac.plot(f["time"], f["cells"], label="adaptive")
ac.axhline(128000, color="k", ls="--", label="finest grid (400 x 320)")
ac.set_xlabel("t (D/U)")
ac.set_ylabel("cells")
ac.set_yscale("log")
ac.legend(loc="lower right")
fig.tight_layout()
fig.savefig(out, dpi=110)

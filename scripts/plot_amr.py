"""The periodic planar jet of bench-amr on fv's adaptive grid: the vorticity
on the composite grid at the end with every patch's outline coloured by its
level, and the cell count over time against the uniform finest grid's.

Usage: plot_amr.py OUT_PNG DIR
  DIR   where `bench-amr STEPS --out DIR` wrote amr_cells.csv and amr_jet.h5
"""
import sys

import h5py

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PatchCollection
from matplotlib.patches import Rectangle

out, run = sys.argv[1], sys.argv[2]
cells = np.genfromtxt(f"{run}/amr_cells.csv", delimiter=",", names=True)
# Per level, the cells' own corners (4 per cell), vorticity and level.
x, y, h, omega, level = [], [], [], [], []
with h5py.File(f"{run}/amr_jet.h5", "r") as f:
    for name in sorted(k for k in f if k.endswith("_nodes")):
        p = name[: -len("nodes")]
        nodes = f[name][:].reshape(-1, 4, 3)
        x.append(nodes[:, :, 0].mean(axis=1))
        y.append(nodes[:, :, 1].mean(axis=1))
        h.append(nodes[:, :, 0].max(axis=1) - nodes[:, :, 0].min(axis=1))
        omega.append(f[p + "vorticity"][:, 0])
        level.append(f[p + "level"][:, 0])
snap = {k: np.concatenate(v) for k, v in dict(x=x, y=y, h=h, omega=omega, level=level).items()}
PATCH = 8  # cells per patch edge (bench-amr)

fig, (ax, ac) = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1.15, 1]})
squares = [Rectangle((x - h / 2, y - h / 2), h, h) for x, y, h in zip(snap["x"], snap["y"], snap["h"])]
pc = PatchCollection(squares, cmap="viridis", linewidths=0)
pc.set_array(snap["omega"])
ax.add_collection(pc)
fig.colorbar(pc, ax=ax, label="|vorticity|")
# Patch outlines: a patch is PATCH x PATCH cells of one level.
colours = {0: "white", 1: "orange", 2: "red"}
seen = set()
for x, y, h, level in zip(snap["x"], snap["y"], snap["h"], snap["level"].astype(int)):
    size = PATCH * h
    key = (level, int(x // size), int(y // size))
    if key in seen:
        continue
    seen.add(key)
    ax.add_patch(Rectangle((key[1] * size, key[2] * size), size, size, fill=False, lw=0.6, ec=colours[level]))
ax.set_xlim(0, 2 * np.pi)
ax.set_ylim(0, 2 * np.pi)
ax.set_aspect("equal")
ax.set_xlabel("x")
ax.set_ylabel("y")
ax.set_title("periodic planar jet, |vorticity| on 3 levels\n(patch outlines: white 0, orange 1, red 2)")
ac.plot(cells["t"], cells["cells"], label="adaptive (3 levels, regrid every 5 steps)")
ac.axhline(16384, color="k", ls="--", label="uniform finest grid (128 x 128)")
ac.set_xlabel("t")
ac.set_ylabel("cells")
ac.set_ylim(0, 18000)
ac.legend(loc="lower right")
ac.set_title("cells over time")
fig.tight_layout()
fig.savefig(out, dpi=int(sys.argv[3]) if len(sys.argv) > 3 else 110)

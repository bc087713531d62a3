#!/usr/bin/python3
"""Error of the psm drag against Zick & Homsy vs sphere resolution.

    scripts/plot_drag_resolution.py out/drag-resolution/resolution.csv docs/img/psm_drag_resolution.png
(written by scripts/psm_drag_resolution.sh). Uses Debian's python3 with matplotlib.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
fig, ax = plt.subplots(figsize=(6, 4))
for phi in sorted({r["phi"] for r in rows}):
    sel = [r for r in rows if r["phi"] == phi]
    d = [float(r["diameter_cells"]) for r in sel]
    e = [100 * float(r["error"]) for r in sel]
    ax.plot(d, e, "o-", label=f"phi = {float(phi):.3f}")
ax.axhline(-5, color="grey", ls="--", lw=0.8)
ax.axhline(5, color="grey", ls="--", lw=0.8, label="issue tolerance (5 %)")
ax.axhline(0, color="k", lw=0.5)
ax.axvline(16, color="grey", ls=":", lw=0.8)
ax.set_xlabel("sphere diameter (cells)")
ax.set_ylabel("K error vs Zick & Homsy (%)")
ax.set_title("psm drag on a simple cubic array, tau = 1")
ax.legend()
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)
print(f"wrote {sys.argv[2]}")

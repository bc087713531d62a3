"""The backward-facing step of Driver & Seegmiller (1985) on fv with k-epsilon
and wall functions (configs/validation/fv_ke_backward_step.yaml): the
streamwise velocity with its zero line (the recirculation), and the floor's
first-cell velocity along x/H for each run given, against the measured
reattachment 6.26 +/- 0.10 H.

Usage: plot_backward_step.py OUT_PNG RUN_DIR [RUN_DIR ...]
  RUN_DIR  finished runs of the config (the first one is drawn as a map);
           each labelled by its grid (domain.cells of its config.yaml)
"""
import glob
import re
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def last_velocity(run):
    f = sorted(glob.glob(run + "/fluid/step_*.h5"))[-1]
    with h5py.File(f, "r") as h:
        return h["velocity"][()][0, :, :, 0]  # (y, x) of the first z layer


def cells(run):
    text = open(run + "/config.yaml").read()
    m = re.search(r"cells:\s*\[(\d+),\s*(\d+)", text)
    return int(m.group(1)), int(m.group(2))


def main():
    out, runs = sys.argv[1], sys.argv[2:]
    lx, ly = 40.0, 9.0
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), gridspec_kw={"height_ratios": [1, 1.2]})
    u = last_velocity(runs[0])
    ny, nx = u.shape
    x = (np.arange(nx) + 0.5) * lx / nx
    y = (np.arange(ny) + 0.5) * ly / ny
    shown = x <= 16
    im = top.pcolormesh(x[shown], y, u[:, shown], shading="auto", cmap="RdBu_r", vmin=-0.3, vmax=1.1)
    top.contour(x[shown], y, u[:, shown], levels=[0.0], colors="k", linewidths=1)
    top.axvline(6.26, color="g", ls="--", lw=1)
    top.set_aspect("equal")
    top.set_xlabel("x / H (from the step)")
    top.set_ylabel("y / H")
    top.set_title("u / U (%d x %d cells); black: u = 0; green: measured reattachment" % cells(runs[0]))
    fig.colorbar(im, ax=top, shrink=0.8)
    for i, run in enumerate(runs):
        u = last_velocity(run)
        ny, nx = u.shape
        x = (np.arange(nx) + 0.5) * lx / nx
        bottom.plot(x, u[0, :], color=f"C{i}", lw=1.2, label="%d x %d cells" % cells(run))
    bottom.axhline(0.0, color="k", lw=0.6)
    bottom.axvspan(6.16, 6.36, color="g", alpha=0.3, label="Driver & Seegmiller 6.26 +/- 0.10")
    bottom.set_xlim(0, 16)
    bottom.set_xlabel("x / H")
    bottom.set_ylabel("u / U at the floor's first cells")
    bottom.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main()

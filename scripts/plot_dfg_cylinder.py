"""The DFG benchmark 2D-1 on lbm (configs/validation/lbm_dfg_cylinder.yaml):
the speed around the cylinder at the end of the first run, and each run's
drag coefficient over time against the benchmark's interval (Schäfer &
Turek 1996: c_D 5.57-5.59).

Usage: plot_dfg_cylinder.py OUT_PNG RUN [RUN ...]
  RUN: a run directory (coflow run ... --set run.output.dir=DIR), labelled
  by its cells across the cylinder and its fluid.lbm.bounce_back
"""
import glob
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

D, U_MEAN, RHO = 0.1, 0.2, 1.0  # m, m/s, kg/m^3


def drag(run):
    rows = np.genfromtxt(f"{run}/series/fluid_walls.csv", delimiter=",", names=True)[1:]
    depth, across = depth_and_cells(run)
    return rows["time"], 2 * rows["solid1_fx"] / (RHO * U_MEAN**2 * D * depth), across


def depth_and_cells(run):
    with h5py.File(sorted(glob.glob(f"{run}/fluid/step_*.h5"))[-1]) as f:
        ny = f["velocity"].shape[1]
    return 0.41 / ny, round(D / (0.41 / ny))  # the runs' depth is one cell


def bounce_back(run):
    with open(f"{run}/config.yaml") as f:
        for line in f:
            if line.strip().startswith("bounce_back:"):
                return line.split(":", 1)[1].strip()
    return "halfway"


def main(out, runs):
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), gridspec_kw={"height_ratios": [1, 1.2]})
    with h5py.File(sorted(glob.glob(f"{runs[0]}/fluid/step_*.h5"))[-1]) as f:
        u = f["velocity"][0]
    speed = np.hypot(u[..., 0], u[..., 1])
    ny, nx = speed.shape
    h = 0.41 / ny
    keep = int(1.0 / h)
    im = top.imshow(speed[:, :keep], origin="lower", extent=[0, keep * h, 0, 0.41], cmap="viridis")
    top.add_patch(plt.Circle((0.2, 0.2), D / 2, fill=False, color="w", lw=0.8))
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    fig.colorbar(im, ax=top, label="|u| (m/s)", shrink=0.8)
    top.set_title(f"DFG 2D-1 on lbm, {bounce_back(runs[0])} bounce-back: speed at the end (first 1 m)")
    bottom.axhspan(5.57, 5.59, color="0.85", label="Schäfer & Turek 1996: 5.57-5.59")
    for run in runs:
        t, cd, across = drag(run)
        bottom.plot(t, cd, label=f"{across} cells across the cylinder, {bounce_back(run)} bounce-back")
    bottom.set_ylim(5.3, 6.0)
    bottom.set_xlabel("t (s)")
    bottom.set_ylabel("c_D (each row: the mean since the last)")
    bottom.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])

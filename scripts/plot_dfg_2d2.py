"""The DFG benchmark 2D-2 on lbm (configs/validation/lbm_dfg_cylinder_2d2.yaml):
each run's drag and lift coefficients over its last seconds against the
benchmark's intervals for their maxima (Schäfer & Turek 1996: c_D,max
3.22-3.24, c_L,max 0.99-1.01).

Usage: plot_dfg_2d2.py OUT_PNG RUN [RUN ...]
  RUN: a run directory (coflow run ... --set run.output.dir=DIR), labelled
  by its cells across the cylinder and its fluid.lbm.bounce_back
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from plot_dfg_cylinder import bounce_back, depth_and_cells

D, U_MEAN, RHO, LAST = 0.1, 1.0, 1.0, 1.5  # m, m/s, kg/m^3, s shown


def coefficients(run):
    rows = np.genfromtxt(f"{run}/series/fluid_walls.csv", delimiter=",", names=True)[1:]
    depth, across = depth_and_cells(run)
    q = 0.5 * RHO * U_MEAN**2 * D * depth
    t = rows["time"]
    keep = t > t[-1] - LAST
    return t[keep], rows["solid1_fx"][keep] / q, rows["solid1_fy"][keep] / q, across


def main(out, runs):
    fig, (drag, lift) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    drag.axhspan(3.22, 3.24, color="0.85", label="c_D,max: Schäfer & Turek 1996, 3.22-3.24")
    lift.axhspan(0.99, 1.01, color="0.85", label="c_L,max: 0.99-1.01")
    for run in runs:
        t, cd, cl, across = coefficients(run)
        label = f"{across} cells across, {bounce_back(run)} bounce-back"
        drag.plot(t, cd, label=label)
        lift.plot(t, cl, label=label)
    drag.set_ylabel("c_D")
    lift.set_ylabel("c_L")
    lift.set_xlabel("t (s)")
    drag.set_title("DFG 2D-2 (Re 100) on lbm: the last 1.5 s of 10 s")
    drag.legend(loc="lower right", fontsize=8)
    lift.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])

"""Particle dispersion behind a grid on fv's k-epsilon flow (seed 003 §5.4):
each species' mean-square lateral displacement after x/M = 68.4 (the run's
series/dispersion.csv, eq. 5.24) against the Langevin model's moments in the
fluid's decay (msd_model.csv, written by coflow-check grid_turbulence_fv).

Usage: plot_dispersion.py OUT_PNG RUN_DIR
  RUN_DIR  a finished run of configs/cases/dpm_grid_turbulence_fv.yaml (or the
           validation one) after `coflow-check grid_turbulence_fv RUN_DIR`
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def main():
    out, run = sys.argv[1:3]
    d = np.genfromtxt(run + "/series/dispersion.csv", delimiter=",", names=True, comments="#")
    m = np.genfromtxt(run + "/msd_model.csv", delimiter=",", names=True)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for i, name in enumerate([n[4:] for n in d.dtype.names if n.startswith("msd_")]):
        c = f"C{i}"
        ax.plot(d["t"], 1e4 * d["msd_" + name], "o", ms=3, color=c, label=f"{name} (dpm on fv)")
        ax.plot(m["t"], 1e4 * m["model_" + name], "-", color=c, lw=1)
    ax.set_xlabel("t since x/M = 68.4 (s)")
    ax.set_ylabel("mean-square lateral displacement (cm^2)")
    ax.set_title("grid turbulence, k-epsilon carrier; lines: the model's moments")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()

"""k-epsilon on fv (issue 22): the channel's u+ against Moser, Kim & Mansour's
DNS at Re_tau 392 and the log law, and the decay behind a grid: k along x
against the model's exact decay from the inlet and Snyder & Lumley's law
(seed 003 eqs. 5.21-5.23).

Usage: plot_k_epsilon.py OUT_PNG CHANNEL_RUN GRID_RUN
  CHANNEL_RUN  a finished run of configs/validation/fv_ke_channel.yaml
  GRID_RUN     a finished run of configs/validation/fv_ke_grid_turbulence.yaml
"""
import glob
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import yaml

# MKM 1999 chan395.means rows (y+, U+); the same as
# tests/validation/fv/turbulence_checks.cpp (source in references.csv).
MKM = [(29.858, 13.479), (39.744, 14.290), (50.958, 14.902), (68.804, 15.614), (98.400, 16.493),
       (150.92, 17.664), (198.91, 18.535), (251.08, 19.256), (301.61, 19.758)]


def last(run, name):
    snap = sorted(glob.glob(run + "/fluid/step_*.h5"))[-1]
    with h5py.File(snap) as f:
        return f[name][...]


def channel(ax, run):
    cfg = yaml.safe_load(open(run + "/config.yaml"))
    lo, hi, n = cfg["domain"]["lower"], cfg["domain"]["upper"], cfg["domain"]["cells"]
    delta = 0.5 * (hi[1] - lo[1])
    fl = cfg["fluid"]
    utau = np.sqrt(fl["body_force"][0] * delta / fl["density"])
    nu = fl["viscosity"]
    u = last(run, "velocity")[0, :, :, 0].mean(axis=1)
    dy = (hi[1] - lo[1]) / n[1]
    half = n[1] // 2
    y = (np.arange(half) + 0.5) * dy
    up = 0.5 * (u[:half] + u[::-1][:half]) / utau
    yp = y * utau / nu
    ax.semilogx(yp, up, "-", label="fv, k-epsilon two-layer")
    ax.semilogx(*zip(*MKM), "o", label="DNS, Moser, Kim & Mansour 1999")
    ys = np.logspace(0, np.log10(yp[-1]), 100)
    ax.semilogx(ys, np.minimum(ys, np.log(ys) / 0.41 + 5.2), ":", color="grey", label="u+ = y+; log law")
    ax.axvspan(30, 300, color="0.93")
    ax.set_xlabel("y+")
    ax.set_ylabel("u+")
    ax.set_title(f"channel, Re_tau = {utau * delta / nu:.0f}")
    ax.legend(fontsize=8)


def grid(ax, run):
    cfg = yaml.safe_load(open(run + "/config.yaml"))
    lo, hi, n = cfg["domain"]["lower"], cfg["domain"]["upper"], cfg["domain"]["cells"]
    t = cfg["fluid"]["turbulence"]
    U = cfg["fluid"]["boundaries"]["x-"]["value"][0]
    c2 = t.get("constants", {}).get("C_epsilon2", 1.92)
    M = (hi[0] - lo[0]) / n[0]
    k = last(run, "k")[0].mean(axis=0)
    x = (np.arange(n[0]) + 0.5) * M
    ki, ei = t["inlet"]["k"], t["inlet"]["epsilon"]
    exact = ki * (1 + (c2 - 1) * ei * x / (U * ki)) ** (-1 / (c2 - 1))
    xi = lo[0] / M + x / M
    sl = 0.5 * (U * U / (42.4 * (xi - 16)) + 2 * U * U / (39.4 * (xi - 12)))
    ax.loglog(xi, k, "-", label="fv, k-epsilon")
    ax.loglog(xi[::8], exact[::8], "o", mfc="none", label="model's exact decay from the inlet")
    ax.loglog(xi, sl, "--", label="Snyder & Lumley 1971 (seed 003 eqs. 5.21-5.22)")
    ax.set_xlabel("x / M")
    ax.set_ylabel("k (m^2/s^2)")
    ax.set_title("decay behind a grid, U = 6.55 m/s")
    ax.legend(fontsize=8)


def main():
    out, ch, gr = sys.argv[1:4]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    channel(axes[0], ch)
    grid(axes[1], gr)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()

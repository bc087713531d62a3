#!/usr/bin/python3
"""Impact maps on the plate of the granular jet (seed 003 §5.3, Figs 5.18-5.19, 5.21-5.22).

    scripts/plot_jet_impacts.py OUT_DIR [IMG_DIR]
OUT_DIR holds the runs of scripts/jet_plate_cases.sh (spread_0, spread_5, ...,
nozzle_30, ...). For each run, the impacts on the plate (events/impacts.csv,
mesh walls) are binned on the plate's x-z plane (5 mm bins): mean impact angle
(between velocity and plate, 90 = head-on) and impact frequency (impacts per
second and cm^2 over the run). Writes IMG_DIR/dpm_jet_spread.png and
IMG_DIR/dpm_jet_nozzle.png (IMG_DIR defaults to docs/img). Uses Debian's python3
with numpy and matplotlib.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

edges = np.linspace(0.05, 0.15, 21)
area_cm2 = (edges[1] - edges[0]) ** 2 * 1e4


def binned(out, run):
    """One run's impacts on the plate (its triangles: wall >= 6) on the bins:
    counts n, sums of the angle s, the run's duration (s) and every impact's angle."""
    d = np.genfromtxt(f"{out}/{run}/events/impacts.csv", delimiter=",", names=True)
    d = d[d["wall"] >= 6]
    duration = max(float(np.max(d["time"])), 1e-12)
    n, _, _ = np.histogram2d(d["x"], d["z"], bins=[edges, edges])
    s, _, _ = np.histogram2d(d["x"], d["z"], bins=[edges, edges], weights=d["angle"])
    return n, s, duration, d["angle"]


def maps(out, run):
    n, s, duration, angles = binned(out, run)
    with np.errstate(invalid="ignore", divide="ignore"):
        angle = np.where(n > 0, s / n, np.nan)
    return angle, n / duration / area_cm2, len(angles), float(np.mean(angles))


def figure(out, img, runs, titles, name):
    fig, ax = plt.subplots(2, len(runs), figsize=(3.3 * len(runs), 6.4), squeeze=False)
    data = [maps(out, r) for r in runs]
    fmax = max(np.max(f) for _, f, _, _ in data)
    for k, ((angle, freq, count, mean), title) in enumerate(zip(data, titles)):
        ext = [edges[0] * 100, edges[-1] * 100, edges[0] * 100, edges[-1] * 100]
        im0 = ax[0][k].imshow(angle.T, origin="lower", extent=ext, vmin=0, vmax=90, cmap="viridis")
        ax[0][k].set_title(f"{title}\nmean {mean:.1f} deg, {count} impacts", fontsize=9)
        im1 = ax[1][k].imshow(np.where(freq > 0, freq, np.nan).T, origin="lower", extent=ext, cmap="magma",
                              norm=mcolors.LogNorm(vmin=fmax * 1e-4, vmax=fmax))
        for a in (ax[0][k], ax[1][k]):
            a.set_xlabel("x [cm]")
            a.set_ylabel("z [cm]")
    fig.colorbar(im0, ax=ax[0].tolist(), label="mean impact angle [deg]")
    fig.colorbar(im1, ax=ax[1].tolist(), label="impacts / (s cm^2)")
    fig.savefig(f"{img}/{name}", dpi=100)
    print(f"wrote {img}/{name}")


def main():
    out = sys.argv[1]
    img = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
    os.makedirs(img, exist_ok=True)
    figure(out, img, ["spread_0", "spread_5", "spread_10", "spread_15"],
           ["spread 0 deg", "spread 5 deg", "spread 10 deg", "spread 15 deg"], "dpm_jet_spread.png")
    figure(out, img, ["spread_0", "nozzle_60", "nozzle_45", "nozzle_30"],
           ["nozzle 90 deg", "nozzle 60 deg", "nozzle 45 deg", "nozzle 30 deg"], "dpm_jet_nozzle.png")


if __name__ == "__main__":
    main()

"""Drainage of a bed: the pressure drop across the box against the bed's red
(wetting) saturation, and the phase field at four times (in 3D on the
mid-plane z).

Usage: plot_drainage.py RUN_DIR X_FROM X_TO OUT_PNG
  RUN_DIR   a finished run of configs/drainage.yaml or
            configs/cases/drainage_static_bed.yaml
  X_FROM, X_TO   the bed's extent along x, m (its saturation is taken there);
                 "grains grains": the extent of the DEM grains at each time
"""
import csv
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

run, out = sys.argv[1], sys.argv[4]
by_grains = sys.argv[2] == "grains"


def bed_extent(index):
    """The bed's extent along x, m: given, or that of the grains in particle snapshot `index`."""
    if not by_grains:
        return float(sys.argv[2]), float(sys.argv[3])
    h = h5py.File(f"{run}/particles/step_{index:06d}.h5", "r")
    x, r = h["position"][:, 0], h["radius"][:]
    return (x - r).min(), (x + r).max()


rows = list(csv.reader(open(run + "/fluid/index.csv")))[1:]
times, sat, dp, frames = [], [], [], []
for r in rows:
    h = h5py.File(f"{run}/fluid/step_{int(r[0]):06d}.h5", "r")
    phase = h["phase"][:]  # (z, y, x)
    solid = h["solid_fraction"][:]
    p = h["pressure"][:]
    x0, x1 = bed_extent(int(r[0]))
    i0, i1 = int(round(x0 / 1e-3)), int(round(x1 / 1e-3))  # dx = 1 mm in the cases
    share = 1.0 - solid[:, :, i0:i1]  # the fluid's share of each cell (grains: partially saturated)
    red = 0.5 * (1.0 + phase[:, :, i0:i1])
    times.append(float(r[1]))
    sat.append((red * share).sum() / share.sum())
    dp.append(p[:, :, 0].mean() - p[:, :, -1].mean())
    mid = phase.shape[0] // 2
    frames.append((float(r[1]), phase[mid], solid[mid]))
fig, ax = plt.subplots(1, 2, figsize=(11, 4), gridspec_kw={"width_ratios": [1, 1.6]})
ax[0].plot(sat, 1e3 * np.array(dp), "o-", ms=3)
ax[0].set_xlabel("red (wetting) saturation of the bed")
ax[0].set_ylabel("pressure drop across the box (mPa)")
ax[0].set_xlim(0, 1.02)
ax[0].set_title("drainage, inlet pressure ramped", fontsize=9)
picks = [frames[k] for k in np.linspace(len(frames) // 4, len(frames) - 1, 4).astype(int)]
strip = np.concatenate([np.where(s > 0.5, np.nan, ph) for _, ph, s in picks], axis=0)
im = ax[1].imshow(strip, origin="lower", cmap="coolwarm", vmin=-1, vmax=1, aspect="equal")
ny = picks[0][1].shape[0]
for k, (t, _, _) in enumerate(picks):
    ax[1].text(3, k * ny + 4, f"t = {t:.0f} s", fontsize=8)
ax[1].set_title("phase: red +1, blue -1 (grains blank), four times", fontsize=9)
ax[1].set_xticks([])
ax[1].set_yticks([])
fig.colorbar(im, ax=ax[1], fraction=0.03)
fig.tight_layout()
fig.savefig(out, dpi=110)
print(f"{len(times)} snapshots; final saturation {sat[-1]:.3f} at {1e3 * dp[-1]:.3f} mPa")

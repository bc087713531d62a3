#!/usr/bin/python3
"""Grid-turbulence dispersion plot (seed 003 §5.4, Fig. 5.23-5.24) for docs/validation.md.

    scripts/plot_grid_turbulence.py RUN_CT022 RUN_CT026 [OUT_DIR]
Each RUN is a run of configs/validation/dpm_grid_turbulence.yaml (the second with
--set particles.dispersion.C_T=0.26) after `coflow-check grid_turbulence RUN`,
which writes RUN/msd.csv: the mean-square lateral displacement after the reset
at x/M = 68.4 per particle kind of Table 5.7, and the model's moment equations.
The ctests leave them in build/tests/val-dpm_grid_turbulence*/run. OUT_DIR
defaults to docs/img. Uses Debian's python3 with numpy and matplotlib.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

runs = {0.22: sys.argv[1], 0.26: sys.argv[2]}
out = sys.argv[3] if len(sys.argv) > 3 else "docs/img"
os.makedirs(out, exist_ok=True)
stokes = {"p1": 0.44, "p2": 5.87, "p3": 14.69, "p4": 14.93}


def read(run):
    rows = list(csv.DictReader(open(f"{run}/msd.csv")))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


data = {ct: read(run) for ct, run in runs.items()}
fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
d = data[0.22]
for i, (name, st) in enumerate(stokes.items()):
    c = f"C{i}"
    ax[0].plot(d["tau"], [1e4 * v for v in d[f"msd_{name}"]], "o", ms=3, color=c,
               label=f"{name} (St {st}), 2000 trajectories")
    ax[0].plot(d["tau"], [1e4 * v for v in d[f"model_{name}"]], "-", color=c, lw=1)
ax[0].set_title("C_T = 0.22: dpm (dots), model moment equations (lines)")
for ct, style in ((0.22, "o"), (0.26, "s")):
    d = data[ct]
    ax[1].plot(d["tau"], [1e4 * v for v in d["msd_p2"]], style, ms=3, label=f"p2, C_T = {ct}")
    ax[1].plot(d["tau"], [1e4 * v for v in d["model_p2"]], "-", color="k", lw=0.8)
ax[1].set_title("particle 2 (87 um, 1000 kg/m3): C_T 0.22 and 0.26")
for a in ax:
    a.set_xlabel("time after x/M = 68.4 [s]")
    a.set_ylabel("mean-square lateral displacement [cm^2]")
    a.grid(alpha=0.3)
    a.legend(fontsize=8)
fig.tight_layout()
fig.savefig(f"{out}/dpm_grid_turbulence.png", dpi=110)
print(f"wrote {out}/dpm_grid_turbulence.png")

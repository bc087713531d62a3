#!/usr/bin/python3
"""The granular jet on the plate (seed 003 §5.3) in still air (the dry case,
configs/cases/dpm_jet_plate.yaml) and with the air computed by fv around the
plate and coupled both ways (configs/cases/dpm_jet_plate_fv.yaml): impact
speeds and their mean over time, from each run's events/impacts.csv.

  scripts/plot_jet_wet_dry.py DRY_RUN WET_RUN OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def impacts(run):
    with open(f"{run}/events/impacts.csv") as f:
        rows = list(csv.DictReader(f))
    return np.array([[float(r["time"]), float(r["speed"]), float(r["angle"])] for r in rows])


def main(dry_dir, wet_dir, out):
    dry, wet = impacts(dry_dir), impacts(wet_dir)
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    bins = np.linspace(min(dry[:, 1].min(), wet[:, 1].min()), max(dry[:, 1].max(), wet[:, 1].max()), 60)
    for data, label in ((dry, "still air (prescribed)"), (wet, "air computed (fv + ibm, two-way)")):
        a.hist(data[:, 1], bins=bins, histtype="step", label=f"{label}: {len(data)} impacts")
        edges = np.linspace(data[:, 0].min(), data[:, 0].max(), 21)
        which = np.digitize(data[:, 0], edges)
        t = [data[which == k, 0].mean() for k in range(1, len(edges)) if np.any(which == k)]
        v = [data[which == k, 1].mean() for k in range(1, len(edges)) if np.any(which == k)]
        b.plot(np.array(t) * 1e3, v, "o-", ms=3, label=label)
    a.set_xlabel("impact speed (m/s)")
    a.set_ylabel("impacts")
    a.legend(fontsize=8)
    b.set_xlabel("time (ms)")
    b.set_ylabel("mean impact speed (m/s)")
    b.legend(fontsize=8)
    fig.suptitle("Granular jet on a plate, no particle-particle collisions (seed 003 §5.3)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])

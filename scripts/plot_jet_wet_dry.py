#!/usr/bin/python3
"""The granular jet on the plate (seed 003 §5.3) in still air (the dry case,
configs/cases/dpm_jet_plate.yaml) and with the air computed by fv around the
plate and coupled both ways (configs/cases/dpm_jet_plate_fv.yaml), from each
run's events/impacts.csv: without particle-particle collisions the impact
speeds, their mean over time and the impact angles; with them (the two
optional runs) the impact angles and speeds.

  scripts/plot_jet_wet_dry.py DRY_RUN WET_RUN OUT.png [DRY_PP_RUN WET_PP_RUN]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

LABELS = ("still air (prescribed)", "air computed (fv + ibm, two-way)")


def impacts(run):
    with open(f"{run}/events/impacts.csv") as f:
        rows = list(csv.DictReader(f))
    return np.array([[float(r["time"]), float(r["speed"]), float(r["angle"])] for r in rows])


def histograms(ax, runs, column, bins, xlabel):
    for data, label in zip(runs, LABELS):
        ax.hist(data[:, column], bins=bins, histtype="step", label=f"{label}: {len(data)} impacts")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("impacts")
    ax.legend(fontsize=7)


def mean_over_time(ax, runs):
    for data, label in zip(runs, LABELS):
        edges = np.linspace(data[:, 0].min(), data[:, 0].max(), 21)
        which = np.digitize(data[:, 0], edges)
        t = [data[which == k, 0].mean() for k in range(1, len(edges)) if np.any(which == k)]
        v = [data[which == k, 1].mean() for k in range(1, len(edges)) if np.any(which == k)]
        ax.plot(np.array(t) * 1e3, v, "o-", ms=3, label=label)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("mean impact speed (m/s)")
    ax.legend(fontsize=7)


def main(dry_dir, wet_dir, out, dry_pp=None, wet_pp=None):
    runs = (impacts(dry_dir), impacts(wet_dir))
    pp = (impacts(dry_pp), impacts(wet_pp)) if dry_pp else None
    fig, axes = plt.subplots(2 if pp else 1, 3, figsize=(14, 8 if pp else 4), squeeze=False)
    speeds = np.concatenate([r[:, 1] for r in runs])
    histograms(axes[0][0], runs, 1, np.linspace(speeds.min(), speeds.max(), 60), "impact speed (m/s)")
    mean_over_time(axes[0][1], runs)
    # Head-on in still air (exactly 90 degrees); the computed air turns them by hundredths of a degree.
    angles = np.concatenate([r[:, 2] for r in runs])
    histograms(axes[0][2], runs, 2, np.linspace(min(angles.min(), 89.9), 90.0, 41), "impact angle (degrees)")
    axes[0][2].set_yscale("log")
    for ax, what in zip(axes[0], ("speeds", "mean speed", "angles")):
        ax.set_title(f"no particle-particle collisions: {what}", fontsize=9)
    if pp:
        histograms(axes[1][0], pp, 2, np.linspace(0.0, 90.0, 46), "impact angle (degrees)")
        speeds = np.concatenate([r[:, 1] for r in pp])
        histograms(axes[1][1], pp, 1, np.linspace(0.0, speeds.max(), 60), "impact speed (m/s)")
        axes[1][1].set_yscale("log")
        mean_over_time(axes[1][2], pp)
        for ax, what in zip(axes[1], ("angles", "speeds", "mean speed")):
            ax.set_title(f"with particle-particle collisions: {what}", fontsize=9)
    fig.suptitle("Granular jet on a plate in still and in computed air (seed 003 §5.3)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) not in (4, 6):
        sys.exit(__doc__)
    main(*sys.argv[1:])

#!/usr/bin/python3
"""The granular jet's impact maps (seed 003 §5.3) reduced to the figures its text speaks of.

    scripts/jet_seed_statements.py OUT_DIR [RUN ...]

OUT_DIR holds runs of scripts/jet_plate_cases.sh (default runs: no_pp,
spread_0/5/10/15, nozzle_60/45/30). The seed's Figs 5.16, 5.18-5.19 and
5.21-5.22 are maps whose values its text does not give; what the text states
is compared here (docs/validation.md, "Granular jet on a plate"). Per run, on
the 5 mm bins of scripts/plot_jet_impacts.py:
  - impacts, and the mean and range of the impact angle over all impacts;
  - the range of the bins' mean angle (bins with at least MIN_COUNT impacts):
    the colour range of the seed's angle maps;
  - the impact area: the bins hit at 1 % of the peak frequency or more, cm^2;
  - the peak frequency, impacts per second and cm^2;
  - the slope of the bins' mean angle along x (degrees per cm, weighted by
    the bins' impacts): the seed's "the mean angle falls towards +x";
  - the direct spot: each particle's first strike on the plate, its area as
    4 pi sqrt(det C), C the covariance of those strikes' (x, z) (the area of
    an ellipse struck uniformly; no bins), cm^2.
Uses Debian's python3 with numpy.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_jet_impacts import area_cm2, binned, edges  # noqa: E402  (the maps' bins)

MIN_COUNT = 20
centres_cm = 0.5 * (edges[1:] + edges[:-1]) * 100


def summary(out, run):
    n, s, duration, angles = binned(out, run)
    full = n >= MIN_COUNT
    mean = np.where(full, s / np.maximum(n, 1), np.nan)
    freq = n / duration / area_cm2
    xs = np.repeat(centres_cm[:, None], len(centres_cm), axis=1)
    w = np.where(full, n, 0.0)
    xm = np.sum(w * xs) / np.sum(w)
    slope = np.sum(w * (xs - xm) * np.nan_to_num(mean)) / np.sum(w * (xs - xm) ** 2)
    hit = freq >= 0.01 * np.max(freq)
    return (len(angles), float(np.mean(angles)), float(np.min(angles)), float(np.max(angles)),
            float(np.nanmin(mean)), float(np.nanmax(mean)), float(np.sum(hit)) * area_cm2, float(np.max(freq)), slope)


def direct_spot_cm2(out, run):
    """The area of the particles' first strikes on the plate: 4 pi sqrt(det C) (cm^2)."""
    d = np.genfromtxt(f"{out}/{run}/events/impacts.csv", delimiter=",", names=True)
    d = d[d["wall"] >= 6]
    d = d[np.lexsort((d["time"], d["id"]))]
    first = np.ones(len(d), dtype=bool)
    first[1:] = d["id"][1:] != d["id"][:-1]
    c = np.cov(np.vstack((d["x"][first], d["z"][first])) * 100)
    return 4 * np.pi * np.sqrt(max(np.linalg.det(c), 0.0))


def main():
    out = sys.argv[1]
    runs = sys.argv[2:] or ["no_pp", "spread_0", "spread_5", "spread_10", "spread_15", "nozzle_60", "nozzle_45",
                            "nozzle_30"]
    print("| run | impacts | mean angle | angle range | bins' mean angle range | area (cm^2) "
          "| peak frequency (1/(s cm^2)) | d(mean angle)/dx (deg/cm) | direct spot (cm^2) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for run in runs:
        c, m, lo, hi, blo, bhi, area, peak, slope = summary(out, run)
        print(f"| {run} | {c} | {m:.1f} | {lo:.1f}-{hi:.1f} | {blo:.1f}-{bhi:.1f} | {area:.1f} | {peak:.3g} "
              f"| {slope:+.2f} | {direct_spot_cm2(out, run):.3f} |")


main()

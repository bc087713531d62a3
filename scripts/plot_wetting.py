"""Contact angle measured against the angle asked for, per wetting condition.

Usage: plot_wetting.py WETTING_CSV OUT_PNG (scripts/two_phase_wetting_cases.sh writes the CSV).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = list(csv.DictReader(open(sys.argv[1])))
fig, ax = plt.subplots(figsize=(5, 4.5))
ax.fill_between([0, 180], [-3, 177], [3, 183], color="0.9", label="within 3 degrees")
ax.plot([0, 180], [0, 180], "k-", lw=0.8)
for wetting, marker, label in [("geometric", "o", "geometric (Leclaire et al. 2017), default"),
                               ("seed", "s", "seed: fixed solid colour cos(theta)")]:
    pts = [(float(r["asked"]), float(r["measured"])) for r in rows if r["wetting"] == wetting]
    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker, ls="-", label=label)
ax.set_xlabel("contact angle asked for (degrees)")
ax.set_ylabel("contact angle measured (degrees, circle fit)")
ax.set_xlim(0, 180)
ax.set_ylim(0, 180)
ax.set_title("droplet on a wall, D2Q9, 25-cell half-disc, 10^4 steps", fontsize=9)
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)

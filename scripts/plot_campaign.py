#!/usr/bin/env python3
"""Plot of a campaign's summary (ppp_campaign writes DIR/summary.csv).

usage: plot_campaign.py DIR   -> DIR/summary.png

Top: per PPP job (stations and bags), the mean 3D error and the first-15-min mean 3D error [cm]
(jobs with a truth), grouped by station (or bag entry) and ordered as in the manifest; jobs that
did not finish are marked. Bottom: the fixed share of the PPP-AR jobs. Prints the
path of the figure.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = sys.argv[1]
    with open(f"{out}/summary.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["kind"] in ("ppp", "bag")]
    if not rows:
        print("plot_campaign: no PPP jobs to plot")
        return 0
    x = range(len(rows))
    labels = [r["id"] for r in rows]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(max(6, 0.35 * len(rows) + 2), 6), sharex=True)
    mean = [number(r["mean_3d_cm"]) for r in rows]
    first = [number(r["first15_mean_3d_cm"]) for r in rows]
    top.bar([i - 0.2 for i in x], [m or 0 for m in mean], width=0.4, label="mean 3D")
    top.bar([i + 0.2 for i in x], [m or 0 for m in first], width=0.4, label="first 15 min mean 3D")
    for i, r in enumerate(rows):
        if r["state"] != "done":
            top.annotate(r["state"], (i, 0), rotation=90, ha="center", va="bottom", color="red")
    top.set_ylabel("3D error [cm]")
    top.set_title(f"campaign {out}: {len(rows)} PPP jobs (errors where a truth is given)")
    top.legend()
    share = [number(r["fixed_share"]) for r in rows]
    bottom.bar(list(x), [s or 0 for s in share], color="tab:green")
    bottom.set_ylabel("fixed share")
    bottom.set_ylim(0, 1)
    bottom.set_xticks(list(x))
    bottom.set_xticklabels(labels, rotation=90, fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{out}/summary.png", dpi=100)
    print(f"plot: {out}/summary.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())

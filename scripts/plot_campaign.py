#!/usr/bin/env python3
"""Plot of a campaign's summary (ppp_campaign writes DIR/summary.csv).

usage: plot_campaign.py DIR   -> DIR/summary.png [, DIR/summary_ar_cdf.png]

Top: per PPP job (stations and bags), the mean 3D error and the first-15-min mean 3D error [cm]
(jobs with a truth), grouped by station (or bag entry) and ordered as in the manifest; jobs that
did not finish are marked. Bottom: the fixed share of the PPP-AR jobs. Prints the
path of the figure.

With DIR/summary_ar.csv (the PPP-AR figures of every done job and solution) and at least one
fixed epoch: DIR/summary_ar_cdf.png, the empirical CDFs of the time to first fix and of the time
below 10 cm for good, one line per station (colour) and solution (line style) over its restarts
(jobs from a start time; all runs when a station has no restarts). A run that never fixed (never
stayed below 10 cm) is counted but has no step, so its line ends below 1.
"""
import csv
import json
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
    plt.close(fig)
    print(f"plot: {out}/summary.png")
    plot_ar_cdf(out)
    return 0


def minutes(text):
    """Minutes of a summary_ar.csv cell: a number, inf for "never", None when empty."""
    if text == "never":
        return float("inf")
    return number(text)


def campaign_name(out):
    try:
        with open(f"{out}/summary.json") as f:
            return json.load(f).get("campaign", out)
    except (OSError, ValueError):
        return out


def ar_lines(rows):
    """(station, solution) -> rows, the restarts only where a station has any."""
    with_restarts = {r["group"] for r in rows if r["runs"] == "restarts"}
    lines = {}
    for r in rows:
        if r["group"] in with_restarts and r["runs"] != "restarts":
            continue
        lines.setdefault((r["group"], r["solution"]), []).append(r)
    return lines


def plot_ar_cdf(out):
    try:
        with open(f"{out}/summary_ar.csv", newline="") as f:
            rows = list(csv.DictReader(f))
    except FileNotFoundError:
        return
    if not any(int(r["fixed_epochs"] or 0) > 0 for r in rows):
        return
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    panels = [("first_fix_min", "time to first fix [min]"), ("below_10cm_min", "time below 10 cm for good [min]")]
    lines = ar_lines(rows)
    stations = list(dict.fromkeys(station for station, _ in lines))
    styles = {"ekf": "-", "smoother_filtered": "--", "smoother_smoothed": ":"}
    for ax, (key, title) in zip(axes, panels):
        for (station, solution), runs in lines.items():
            values = [minutes(r[key]) for r in runs]
            values = [v for v in values if v is not None]
            if not values:
                continue
            reached = sorted(v for v in values if v != float("inf"))
            never = len(values) - len(reached)
            if not reached:
                continue
            xs = [reached[0]] + reached
            ys = [0.0] + [(k + 1) / len(values) for k in range(len(reached))]
            label = f"{station} {solution} ({len(values)} runs" + (f", {never} never" if never else "") + ")"
            ax.step(xs, ys, where="post", label=label, color=f"C{stations.index(station) % 10}",
                    linestyle=styles.get(solution, "-."))
        ax.set_xlabel(title)
        ax.set_ylabel("fraction of runs")
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    fig.suptitle(f"PPP-AR of campaign {campaign_name(out)}: CDF over the runs")
    fig.tight_layout()
    fig.savefig(f"{out}/summary_ar_cdf.png", dpi=80)
    plt.close(fig)
    print(f"plot: {out}/summary_ar_cdf.png")


if __name__ == "__main__":
    sys.exit(main())

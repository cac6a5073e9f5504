#!/usr/bin/env python3
"""Integer residuals of the held narrow lanes, per satellite system.

usage: nl_residual_histogram.py [--png FILE] [--bin CYCLES] LABEL=NL_CSV [LABEL=NL_CSV ...]

Each NL_CSV is what `ppp_ar_study --nl-csv` writes: one row per epoch and single
difference (time_s, satellite, reference, wide_lane, float_cycles, sigma_cycles,
held_cycles). The integer residual of a held single difference is its float narrow
lane minus the integer it is held at (cycles; one narrow-lane cycle is about 10.7 cm
for GPS L1/L2 and Galileo E1/E5a). Right integers with honest products put the
residuals within a few hundredths of a cycle of 0; a wrong integer, or an antenna or
bias model off the products' own, shows as a shifted or widened distribution of its
system.

Prints, per label and system: the count, mean, standard deviation, RMS, the 95th
percentile of |residual|, the share within 0.15 cycle, the held floats' median formal
sigma and the RMS of residual / sigma (about 1 when the float covariance is honest),
and the histogram (share per bin
of --bin cycles, default 0.05, from -0.5 to 0.5). --png also plots the histograms
(python3-matplotlib).
"""
import csv
import math
import sys

SYSTEMS = {"G": "GPS", "E": "Galileo", "C": "BeiDou", "R": "GLONASS", "J": "QZSS"}


def residuals(path):
    """System letter -> list of (float - held integer, float sigma) [cycles] over the held rows of `path`."""
    out = {}
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        for row in reader:
            held = row.get("held_cycles", "")
            if not held:
                continue
            try:
                r = float(row["float_cycles"]) - float(held)
                sigma = float(row["sigma_cycles"])
            except ValueError:
                sys.exit(f"{path}: line {reader.line_num}: float, sigma or held cycles is no number")
            if not (math.isfinite(r) and math.isfinite(sigma) and sigma > 0):
                continue
            out.setdefault(row["satellite"][:1], []).append((r, sigma))
    return out


def percentile(values, p):
    s = sorted(values)
    k = (len(s) - 1) * p
    lo, hi = int(math.floor(k)), int(math.ceil(k))
    return s[lo] + (s[hi] - s[lo]) * (k - lo)


def statistics(pairs):
    values = [r for r, _ in pairs]
    n = len(values)
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else 0.0
    rms = math.sqrt(sum(v * v for v in values) / n)
    within = sum(abs(v) < 0.15 for v in values) / n
    sigma = percentile([s for _, s in pairs], 0.5)
    normalized = math.sqrt(sum((r / s) ** 2 for r, s in pairs) / n)
    return n, mean, sd, rms, percentile([abs(v) for v in values], 0.95), within, sigma, normalized


def histogram(pairs, width):
    values = [r for r, _ in pairs]
    bins = int(round(1.0 / width))
    counts = [0] * bins
    for v in values:
        k = min(bins - 1, max(0, int(math.floor((v + 0.5) / width))))
        counts[k] += 1
    return [c / len(values) for c in counts]


def main(argv):
    png, width, sets = None, 0.05, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--png", "--bin") and i + 1 < len(argv):
            if a == "--png":
                png = argv[i + 1]
            else:
                width = float(argv[i + 1])
            i += 2
            continue
        if "=" not in a:
            sys.exit(__doc__)
        label, path = a.split("=", 1)
        sets.append((label, path, residuals(path)))
        i += 1
    if not sets or not (0.0 < width <= 0.5):
        sys.exit(__doc__)
    print("| data | system | held values | mean | sd | RMS | p95 abs | within 0.15 | float sigma (median) |"
          " RMS(residual / sigma) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, _, by_sys in sets:
        for s in sorted(by_sys):
            n, mean, sd, rms, p95, within, sigma, normalized = statistics(by_sys[s])
            print(f"| {label} | {SYSTEMS.get(s, s)} | {n} | {mean:+.3f} | {sd:.3f} | {rms:.3f} | {p95:.3f} | "
                  f"{100 * within:.1f} % | {sigma:.3f} | {normalized:.2f} |")
    edges = [-0.5 + k * width for k in range(int(round(1.0 / width)) + 1)]
    print()
    print("| data | system | " + " | ".join(f"{edges[k]:+.2f}" for k in range(len(edges) - 1)) + " |")
    print("|---|---|" + "---|" * (len(edges) - 1))
    for label, _, by_sys in sets:
        for s in sorted(by_sys):
            shares = histogram(by_sys[s], width)
            print(f"| {label} | {SYSTEMS.get(s, s)} | " + " | ".join(f"{100 * x:.1f}" for x in shares) + " |")
    print("(share in % per bin of", width, "cycle; the header gives each bin's lower edge)")
    if png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for label, _, by_sys in sets:
            for s in sorted(by_sys):
                ax.stairs(histogram(by_sys[s], width), edges, label=f"{label} {SYSTEMS.get(s, s)} (n={len(by_sys[s])})")
        ax.set_xlabel("float minus held integer [narrow-lane cycles]")
        ax.set_ylabel("share per bin")
        ax.set_xlim(-0.5, 0.5)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(png, dpi=110)
        print("plot:", png)


if __name__ == "__main__":
    main(sys.argv[1:])

#!/usr/bin/env python3
"""Figures from ppp_solve output (Debian python3-matplotlib).

usage: plot_solutions.py --out DIR [--title T] [--window-min 15] LABEL=FILE.csv [LABEL=FILE.csv ...]
                         [--biases LABEL=FILE_biases.csv ...] [--arcs 4]
                         [--residuals LABEL=FILE_residuals.csv ...]

Each FILE.csv is a per-epoch solution CSV written by ppp_solve with --truth
(columns time_gpst, err3d_m, ...). Writes:
  DIR/error_profile.png   3D error (RSOS) versus time, every estimator on one axis
  DIR/cdf.png             CDF of the 3D error, all epochs and the first WINDOW minutes
  DIR/biases.png          phase-bias estimates versus time for a few arcs (when
                          --biases files with columns time_gpst,arc,sat,bias_m are given),
                          minus each arc's final smoothed value (column smoothed_final_m
                          when present, as ppp_solve's <name>_smoother_biases.csv has;
                          else the arc's last value)
  DIR/residuals_LABEL.png postfit IF code and phase residuals versus time, one colour per
                          satellite (when --residuals files are given: ppp_solve's
                          <name>_<estimator>_residuals.csv, columns time_gpst, sat,
                          elevation_deg, code_postfit_m, phase_postfit_m; blank = not used)
Prints the numbers behind each figure: percentiles of the 3D error; per plotted
arc the first, last and final smoothed value and the time after which the filtered
bias stays within 5 cm of the final smoothed value; per satellite the epochs, mean
elevation, and mean and RMS of the postfit code [cm] and phase [mm] residuals (a
code mean far from 0 over a whole arc is a constant code offset, not noise).
"""
import argparse
import csv
import datetime as dt
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def parse_time(text):
    return dt.datetime.fromisoformat(text.strip().replace("Z", ""))


def read_errors(path):
    times, errors = [], []
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        if "err3d_m" not in (reader.fieldnames or []):
            sys.exit(f"{path}: no err3d_m column (run ppp_solve with --truth)")
        for line_no, row in enumerate(reader, start=2):
            if not row["err3d_m"]:
                continue  # a "no solution" epoch
            try:
                times.append(parse_time(row["time_gpst"]))
                errors.append(float(row["err3d_m"]))
            except ValueError as err:
                sys.exit(f"{path}:{line_no}: {err}")
    if not times:
        sys.exit(f"{path}: no solution epochs")
    return times, errors


def percentile(values, p):
    s = sorted(values)
    k = (len(s) - 1) * p / 100.0
    lo, hi = int(k), min(int(k) + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (k - lo)


def cdf_points(values):
    s = sorted(values)
    return s, [(i + 1) / len(s) for i in range(len(s))]


def read_residuals(path):
    """{sat: [(time, elevation_deg, code_postfit_m or None, phase_postfit_m or None)]}"""
    per_sat = {}
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"time_gpst", "sat", "elevation_deg", "code_postfit_m", "phase_postfit_m"} - set(reader.fieldnames or [])
        if missing:
            sys.exit(f"{path}: missing columns {sorted(missing)}")
        for line_no, row in enumerate(reader, start=2):
            try:
                code = float(row["code_postfit_m"]) if row["code_postfit_m"] else None
                phase = float(row["phase_postfit_m"]) if row["phase_postfit_m"] else None
                per_sat.setdefault(row["sat"], []).append(
                    (parse_time(row["time_gpst"]), float(row["elevation_deg"]), code, phase))
            except ValueError as err:
                sys.exit(f"{path}:{line_no}: {err}")
    if not per_sat:
        sys.exit(f"{path}: no residual rows")
    return per_sat


def mean_rms(values):
    if not values:
        return float("nan"), float("nan")
    return sum(values) / len(values), (sum(v * v for v in values) / len(values)) ** 0.5


def plot_residuals(label, path, start, out_dir):
    per_sat = read_residuals(path)
    fig, axes = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    colours = plt.get_cmap("tab20").colors  # up to 20 satellites in distinct colours
    print(f"{'residuals':24s} {'sat':>4s} {'epochs':>7s} {'elev deg':>9s} {'code mean cm':>13s} {'code rms cm':>12s} "
          f"{'phase mean mm':>14s} {'phase rms mm':>13s}")
    for k, sat in enumerate(sorted(per_sat)):
        rows = per_sat[sat]
        colour = colours[k % len(colours)]
        minutes = [(t - start).total_seconds() / 60 for t, *_ in rows]
        code = [c for *_, c, _ in rows if c is not None]
        phase = [p for *_, p in rows if p is not None]
        axes[0].plot([m for m, r in zip(minutes, rows) if r[2] is not None], [c * 100 for c in code], ".", ms=3, label=sat,
                     color=colour)
        axes[1].plot([m for m, r in zip(minutes, rows) if r[3] is not None], [p * 1000 for p in phase], ".", ms=3, color=colour)
        cm, cr = mean_rms(code)
        pm, pr = mean_rms(phase)
        elev = sum(r[1] for r in rows) / len(rows)
        print(f"{label:24s} {sat:>4s} {len(rows):7d} {elev:9.1f} {cm * 100:13.1f} {cr * 100:12.1f} "
              f"{pm * 1000:14.1f} {pr * 1000:13.1f}")
    axes[0].set_ylabel("postfit IF code residual [cm]")
    axes[1].set_ylabel("postfit IF phase residual [mm]")
    axes[1].set_xlabel("time since start [min]")
    axes[0].set_title(f"{label}: postfit residuals per satellite")
    for ax in axes:
        ax.axhline(0, color="grey", lw=0.8)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=6, ncol=8, markerscale=3)
    fig.tight_layout()
    safe = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in label)
    fig.savefig(os.path.join(out_dir, f"residuals_{safe}.png"), dpi=110)


def labelled(items):
    out = []
    for item in items:
        if "=" not in item:
            sys.exit(f"expected LABEL=FILE, got {item!r}")
        label, path = item.split("=", 1)
        out.append((label, path))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--window-min", type=float, default=15.0)
    ap.add_argument("--biases", nargs="*", default=[])
    ap.add_argument("--arcs", type=int, default=4, help="arcs to plot (the longest)")
    ap.add_argument("--residuals", nargs="*", default=[])
    ap.add_argument("solutions", nargs="+")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    series = [(label, *read_errors(path)) for label, path in labelled(args.solutions)]
    start = min(t[0] for _, t, _ in series)

    fig, ax = plt.subplots(figsize=(9, 4.5))
    for k, (label, times, errors) in enumerate(series):
        # Wider, paler lines first so that identical series (EKF and smoother filtered) both stay visible.
        ax.plot([(t - start).total_seconds() / 60 for t in times], [e * 100 for e in errors], label=label,
                lw=max(1.2, 3.5 - 1.2 * k), alpha=0.6 if k < len(series) - 1 else 1.0)
    ax.axhline(10, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("time since start [min]")
    ax.set_ylabel("3D error (RSOS) [cm]")
    ax.set_yscale("log")
    ax.set_title(args.title or "3D position error profile")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "error_profile.png"), dpi=110)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
    print(f"{'estimator':24s} {'window':>8s} {'p50 cm':>8s} {'p68 cm':>8s} {'p95 cm':>8s} {'max cm':>8s}")
    for k, (label, times, errors) in enumerate(series):
        first = [e for t, e in zip(times, errors) if (t - start).total_seconds() < args.window_min * 60]  # as position_error_statistics.h
        for ax, values, name in ((axes[0], errors, "all"), (axes[1], first, f"{args.window_min:g} min")):
            xs, ys = cdf_points([v * 100 for v in values])
            ax.plot(xs, ys, label=label, lw=max(1.2, 3.5 - 1.2 * k), alpha=0.6 if k < len(series) - 1 else 1.0)
            print(f"{label:24s} {name:>8s} {percentile(values, 50)*100:8.2f} {percentile(values, 68)*100:8.2f} "
                  f"{percentile(values, 95)*100:8.2f} {max(values)*100:8.2f}")
    axes[0].set_title("CDF of the 3D error, all epochs")
    axes[1].set_title(f"CDF of the 3D error, first {args.window_min:g} min")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_xlabel("3D error [cm]")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("fraction of epochs")
    axes[1].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "cdf.png"), dpi=110)

    if args.biases:
        fig, ax = plt.subplots(figsize=(9, 4.5))
        print(f"{'biases':24s} {'arc':>8s} {'epochs':>7s} {'first-final cm':>15s} {'last-final cm':>14s} "
              f"{'within 5 cm after min':>22s}")
        for label, path in labelled(args.biases):
            arcs = {}
            finals = {}
            with open(path, newline="") as f:
                reader = csv.DictReader(f)
                missing = {"time_gpst", "arc", "sat", "bias_m"} - set(reader.fieldnames or [])
                if missing:
                    sys.exit(f"{path}: missing columns {sorted(missing)}")
                for row in reader:
                    key = (row["sat"], row["arc"])
                    arcs.setdefault(key, []).append((parse_time(row["time_gpst"]), float(row["bias_m"])))
                    if row.get("smoothed_final_m"):
                        finals[key] = float(row["smoothed_final_m"])
            for (sat, arc), values in sorted(arcs.items(), key=lambda kv: -len(kv[1]))[:args.arcs]:
                final = finals.get((sat, arc), values[-1][1])
                minutes = [(t - start).total_seconds() / 60 for t, _ in values]
                diffs = [(b - final) * 100 for _, b in values]
                ax.plot(minutes, diffs, label=f"{label} {sat} arc {arc}")
                settled = None
                for k in range(len(diffs)):
                    if all(abs(d) < 5.0 for d in diffs[k:]):
                        settled = minutes[k] - minutes[0]
                        break
                print(f"{label:24s} {sat + ' ' + arc:>8s} {len(values):7d} {diffs[0]:15.1f} {diffs[-1]:14.1f} "
                      f"{('%.1f' % settled) if settled is not None else 'never':>22s}")
        ax.axhline(0, color="grey", lw=0.8)
        ax.set_xlabel("time since start [min]")
        ax.set_ylabel("filtered bias minus final smoothed value [cm]")
        ax.set_yscale("symlog", linthresh=5)
        ax.set_title("IF phase-bias estimates against their final smoothed values")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "biases.png"), dpi=110)
    for label, path in labelled(args.residuals):
        plot_residuals(label, path, start, args.out)
    print(f"figures written to {args.out}")


if __name__ == "__main__":
    main()

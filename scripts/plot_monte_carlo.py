#!/usr/bin/env python3
"""Figures of a ppp_monte_carlo study (Debian python3-matplotlib).

usage: plot_monte_carlo.py DIR [--out FIGDIR] [--flight-csv FILE.csv]

Reads the files ppp_monte_carlo wrote into DIR (summary.json, error_cdf.csv,
representative_flight.csv, error_vs_time.csv, bias_convergence.csv) and writes
into FIGDIR (default DIR):
  cdf.png                   CDF of the 3D error: all epochs, and the first window
  representative_flight.png 3D error profile of the representative flight
  error_vs_time.png         3D error vs time since the flight start over all
                            flights: median and 5-95 % band per estimator
  filtered_vs_ekf.png       EKF vs smoother filtered: error quantiles and |x_EKF - x_filtered|
  flight_ekf_vs_filtered.png  with --flight-csv (written by ppp_bench_mc_flight):
                            one flight's 3D errors and satellites used, EKF vs filtered
  bias_convergence.png      phase-bias error (estimate - truth) vs time since the
                            arc start: median and 5-95 % band, and the median |error|
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The EKF and the smoother's filtered solution nearly coincide: the EKF is drawn
# thick and pale underneath so that both stay visible.
STYLE = {"ekf": dict(lw=3.0, alpha=0.45, zorder=1)}
ESTIMATORS = [("ekf", "EKF", "tab:red"),
              ("smoother_filtered", "smoother filtered", "tab:blue"),
              ("smoother_smoothed", "smoother smoothed", "tab:green")]


def read_csv(path):
    if not os.path.exists(path):
        sys.exit(f"{path}: missing (run ppp_monte_carlo first)")
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def column(rows, name, scale=1.0):
    out = []
    for r in rows:
        v = r.get(name, "")
        out.append(float(v) * scale if v not in ("", None) else float("nan"))
    return out


def plot_cdf(d, summary, figdir):
    rows = read_csv(os.path.join(d, "error_cdf.csv"))
    frac = column(rows, "fraction")
    window_min = summary["first_window_s"] / 60.0
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, suffix, title in ((axes[0], "all_m", "all epochs"),
                              (axes[1], "first_window_m", f"first {window_min:g} min")):
        for key, label, color in ESTIMATORS:
            err = column(rows, f"{key}_{suffix}", 100.0)
            ax.plot(err, frac, color=color, label=label, **STYLE.get(key, {}))
        ax.set_xscale("log")
        ax.set_xlabel("3D error [cm]")
        ax.set_title(f"CDF of the 3D error, {title}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("fraction of epochs")
    axes[0].legend(loc="lower right")
    fig.suptitle(f"{summary['flights']} flights, {summary['duration_s'] / 60:g} min at {summary['rate_hz']:g} Hz")
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "cdf.png"), dpi=110)
    plt.close(fig)
    for key, label, _ in ESTIMATORS:
        err = column(rows, f"{key}_all_m", 100.0)
        print(f"cdf {label:18s} all: p50 {err[500]:.1f} cm, p90 {err[900]:.1f} cm, p99 {err[990]:.1f} cm")


def plot_representative(d, summary, figdir):
    rows = read_csv(os.path.join(d, "representative_flight.csv"))
    t = column(rows, "time_s", 1 / 60.0)
    fig, ax = plt.subplots(figsize=(10, 4.2))
    for key, label, color in ESTIMATORS:
        ax.plot(t, column(rows, f"{key}_3d_m", 100.0), color=color, label=label,
                **STYLE.get(key, dict(lw=1, zorder=2)))
    ax.set_yscale("log")
    ax.set_xlabel("time since the flight start [min]")
    ax.set_ylabel("3D error [cm]")
    ax.set_title(f"representative flight #{summary['representative_flight']} "
                 f"({summary.get('representative_profile', '?')}): median EKF mean of all flights")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "representative_flight.png"), dpi=110)
    plt.close(fig)


def plot_bands(path, t_name, figfile, xlabel, ylabel, title, scale, signed, log):
    rows = read_csv(path)
    t = column(rows, t_name, 1 / 60.0)
    fig, axes = plt.subplots(1, 2 if signed else 1, figsize=(12 if signed else 10, 4.4))
    ax = axes[0] if signed else axes
    for key, label, color in ESTIMATORS:
        p50 = column(rows, f"{key}_p50_m", scale)
        ax.plot(t, p50, color=color, label=f"{label} median", **STYLE.get(key, {}))
        ax.fill_between(t, column(rows, f"{key}_p05_m", scale), column(rows, f"{key}_p95_m", scale),
                        color=color, alpha=0.15, label=f"{label} 5-95 %")
    if log:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    if signed:
        ax.axhline(0.0, color="k", lw=0.5)
        ax2 = axes[1]
        for key, label, color in ESTIMATORS:
            ax2.plot(t, column(rows, f"{key}_abs_p50_m", scale), color=color, label=f"{label} median",
                     **STYLE.get(key, {}))
            ax2.plot(t, column(rows, f"{key}_abs_p90_m", scale), color=color, ls="--", label=f"{label} 90 %")
        ax2.set_yscale("log")
        ax2.set_xlabel(xlabel)
        ax2.set_ylabel("|" + ylabel + "|")
        ax2.set_title("absolute error: median and 90th percentile")
        ax2.grid(True, which="both", alpha=0.3)
        ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figfile, dpi=110)
    plt.close(fig)
    return rows


def plot_difference(d, path, summary, figdir):
    """Where the smoother's filtered solution and the EKF differ (relinearization only)."""
    rows = read_csv(path)
    t = column(rows, "time_s", 1 / 60.0)
    ev = read_csv(os.path.join(d, "error_vs_time.csv"))
    te = column(ev, "time_s", 1 / 60.0)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.4))
    ax = axes[0]
    for key, label, color in ESTIMATORS[:2]:
        ax.plot(te, column(ev, f"{key}_p50_m", 100.0), color=color, label=f"{label} median 3D error",
                **STYLE.get(key, {}))
        ax.plot(te, column(ev, f"{key}_p95_m", 100.0), color=color, ls="--", label=f"{label} 95 %")
    ax.plot(t, column(rows, "p50_m", 100.0), color="k", label="|x_EKF - x_filtered| median")
    ax.plot(t, column(rows, "p95_m", 100.0), color="gray", label="|x_EKF - x_filtered| 95 %")
    ax.set_yscale("log")
    ax.set_xlabel("time since the flight start [min]")
    ax.set_ylabel("[cm]")
    ax.set_title("EKF vs smoother filtered: errors and their difference")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    e = column(ev, "ekf_p50_m", 100.0)
    fl = column(ev, "smoother_filtered_p50_m", 100.0)
    ax.plot(te, [b - a for a, b in zip(e, fl)], color="tab:purple", label="median: filtered - EKF")
    e95 = column(ev, "ekf_p95_m", 100.0)
    f95 = column(ev, "smoother_filtered_p95_m", 100.0)
    ax.plot(te, [b - a for a, b in zip(e95, f95)], color="tab:orange", label="95 %: filtered - EKF")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("time since the flight start [min]")
    ax.set_ylabel("difference of the 3D error quantiles [cm]")
    ax.set_title("convergence gain of the smoother's filtered solution (< 0: better)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "filtered_vs_ekf.png"), dpi=110)
    plt.close(fig)


def plot_flight(path, figdir):
    rows = read_csv(path)
    t = column(rows, "time_s", 1 / 60.0)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    for key, label, color in ESTIMATORS[:2]:
        a1.plot(t, column(rows, f"{key}_3d_m", 100.0), color=color, label=label, **STYLE.get(key, dict(lw=1)))
        a2.step(t, column(rows, f"{key}_used"), color=color, label=f"{label}: satellites used",
                **STYLE.get(key, dict(lw=1)))
    a1.set_yscale("log")
    a1.set_ylabel("3D error [cm]")
    a1.set_title(os.path.basename(path))
    a1.grid(True, which="both", alpha=0.3)
    a1.legend()
    a2.set_ylabel("satellites used (0: no solution)")
    a2.set_xlabel("time since the flight start [min]")
    a2.grid(True, alpha=0.3)
    a2.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "flight_ekf_vs_filtered.png"), dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--out", default=None)
    ap.add_argument("--flight-csv", default=None)
    a = ap.parse_args()
    figdir = a.out or a.dir
    os.makedirs(figdir, exist_ok=True)
    with open(os.path.join(a.dir, "summary.json")) as f:
        summary = json.load(f)
    plot_cdf(a.dir, summary, figdir)
    plot_representative(a.dir, summary, figdir)
    plot_bands(os.path.join(a.dir, "error_vs_time.csv"), "time_s", os.path.join(figdir, "error_vs_time.png"),
               "time since the flight start [min]", "3D error [cm]",
               f"3D error over {summary['flights']} flights", 100.0, False, True)
    rows = plot_bands(os.path.join(a.dir, "bias_convergence.csv"), "age_s",
                      os.path.join(figdir, "bias_convergence.png"), "time since the arc start [min]",
                      "bias error [cm]", "IF phase-bias error (estimate - truth)", 100.0, True, False)
    if a.flight_csv:
        plot_flight(a.flight_csv, figdir)
    diff_path = os.path.join(a.dir, "filtered_minus_ekf.csv")
    if os.path.exists(diff_path):
        plot_difference(a.dir, diff_path, summary, figdir)
    for r in rows[:1] + rows[5:6] + rows[29:30] + rows[89:90]:
        print(f"bias age {float(r['age_s']):6.0f} s: " + ", ".join(
            f"{label} |e| p50 {100 * float(r[key + '_abs_p50_m']):.1f} cm"
            for key, label, _ in ESTIMATORS if r.get(key + "_abs_p50_m")))
    print(f"figures in {figdir}")


if __name__ == "__main__":
    main()

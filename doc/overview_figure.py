#!/usr/bin/env python3
"""The README's figure (doc/overview.png): 3D position error over time of the EKF,
the smoother's filtered and its smoothed solution, on two runs:

  top:    the simulated flight of scripts/demo.sh (ROS nodes on a replayed bag, PPP-AR),
          from the CSVs ppp_bag_report writes (DEMO_DIR/sim_survey_*.csv);
  bottom: the real CCJ2 hour, ppp_solve --estimator both (CCJ2_DIR/ccj2_*.csv).

Usage (run with /usr/bin/python3; matplotlib):
  doc/overview_figure.py DEMO_DIR CCJ2_DIR OUT.png
The commands that make the two directories are in doc/evaluation.md.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# (file suffix, label, colour, line width): the EKF drawn wide under the smoother's
# filtered solution, which follows it to the millimetre.
SERIES = [("ekf", "EKF", "tab:red", 2.4),
          ("smoother_filtered", "smoother filtered", "tab:orange", 0.9),
          ("smoother_smoothed", "smoother smoothed", "tab:blue", 0.9)]


def read_solution(path):
    """(minutes since the first epoch, 3D error [cm], fixed flag) per epoch of a ppp_solve CSV."""
    minutes, error_cm, fixed = [], [], []
    t0 = None
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if not row["err3d_m"]:
                continue
            tow_s = float(row["tow_s"]) + 604800.0 * int(row["gps_week"])
            t0 = tow_s if t0 is None else t0
            minutes.append((tow_s - t0) / 60.0)
            error_cm.append(100.0 * float(row["err3d_m"]))
            fixed.append(row["status"] == "ppp-fixed")
    return minutes, error_cm, fixed


def fixed_spans(minutes, fixed):
    """Contiguous spans [start, end] of the fixed epochs, in minutes."""
    spans, start = [], None
    for i, is_fixed in enumerate(fixed):
        if is_fixed and start is None:
            start = minutes[i]
        if start is not None and (not is_fixed or i == len(fixed) - 1):
            spans.append((start, minutes[i]))
            start = None
    return spans


def panel(ax, prefix, title, show_fixed):
    for key, label, colour, width in SERIES:
        minutes, error_cm, fixed = read_solution(f"{prefix}_{key}.csv")
        ax.plot(minutes, error_cm, color=colour, lw=width, alpha=0.45 if key == "ekf" else 1.0, label=label)
        if show_fixed and key == "smoother_filtered":
            for i, (a, b) in enumerate(fixed_spans(minutes, fixed)):
                ax.axvspan(a, b, color="tab:green", alpha=0.12, lw=0,
                           label="ambiguities fixed" if i == 0 else None)
    ax.set_yscale("log")
    ax.set_ylim(0.1, 500)
    ax.axhline(10.0, color="grey", lw=0.6, ls="--")
    ax.set_ylabel("3D error [cm]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", lw=0.3)
    ax.legend(fontsize=8, loc="upper right", ncol=2)


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    demo_dir, ccj2_dir, out = argv[1:]
    fig, axes = plt.subplots(2, 1, figsize=(8, 6.2))
    panel(axes[0], f"{demo_dir}/sim_survey",
          "Simulated UAV survey flight, GPS + Galileo, PPP-AR: both ROS nodes on one replay (scripts/demo.sh)",
          show_fixed=True)
    panel(axes[1], f"{ccj2_dir}/ccj2",
          "Real data: IGS station CCJ2, 1 h at 30 s, GPS float (ppp_solve --estimator both)",
          show_fixed=False)
    axes[1].set_xlabel("time since the first epoch [min]")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""The figure smoother_ins_figure8.svg of doc/gnss_ins.md (plain SVG, no dependencies).

Inputs: the per-epoch CSVs that test_smoother_ins_ambiguity writes to
$SMOOTHER_INS_FIGURE8_CSV (FloatFilteredFollowsTheGnssInsEkfOnTheFigure8), one run
with the readings applied at the interval's start axes and one at the mid attitude.
Usage: smoother_ins_figure8_figure.py START_AXES.csv MID_ATTITUDE.csv OUT.svg
"""
import csv
import sys

W, H, LEFT, TOP, PANEL_H, GAP = 760, 520, 70, 30, 190, 60


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def polyline(rows, key, y_max, top, color, scale=1.0):
    n = max(len(rows) - 1, 1)
    pts = []
    for i, r in enumerate(rows):
        x = LEFT + (W - LEFT - 20) * i / n
        v = min(max(float(r[key]) * scale, -y_max), y_max)
        pts.append(f"{x:.1f},{top + PANEL_H * (1 - v / y_max) if y_max > 0 else top:.1f}")
    return f'<polyline fill="none" stroke="{color}" stroke-width="1.5" points="{" ".join(pts)}"/>'


def panel(top, title, y_label, y_max, y_min=0.0):
    out = [f'<rect x="{LEFT}" y="{top}" width="{W - LEFT - 20}" height="{PANEL_H}" fill="none" stroke="black"/>',
           f'<text x="{LEFT}" y="{top - 8}" font-size="13">{title}</text>',
           f'<text x="5" y="{top + PANEL_H / 2}" font-size="11">{y_label}</text>']
    for frac in (0.0, 0.5, 1.0):
        v = y_min + (y_max - y_min) * frac
        y = top + PANEL_H * (1 - frac)
        out.append(f'<text x="{LEFT - 5}" y="{y + 4:.1f}" font-size="10" text-anchor="end">{v:g}</text>')
    return out


def main():
    old, new, out_path = read(sys.argv[1]), read(sys.argv[2]), sys.argv[3]
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif">',
             '<rect width="100%" height="100%" fill="white"/>']
    top1 = TOP
    parts += panel(top1, "figure8, industrial IMU 100 Hz, float: |smoother_ins - ekf_ins| filtered position",
                   "m", 1.0)
    parts.append(polyline(old, "difference_m", 1.0, top1, "red"))
    parts.append(polyline(new, "difference_m", 1.0, top1, "blue"))
    top2 = TOP + PANEL_H + GAP
    # x accelerometer bias estimate, 1e-3 m/s^2, shown on [-1, 1] (centre line 0).
    parts += panel(top2, "x accelerometer bias estimate [1e-3 m/s^2]", "", 1.0, -1.0)
    half = PANEL_H / 2
    for rows, key, color in ((old, "ba_x_smoother_ins", "red"), (new, "ba_x_smoother_ins", "blue"),
                             (new, "ba_x_ekf_ins", "green")):
        n = max(len(rows) - 1, 1)
        pts = " ".join(f"{LEFT + (W - LEFT - 20) * i / n:.1f},"
                       f"{top2 + half * (1 - min(max(float(r[key]) * 1e3, -1), 1)):.1f}" for i, r in enumerate(rows))
        parts.append(f'<polyline fill="none" stroke="{color}" stroke-width="1.5" points="{pts}"/>')
    parts.append(f'<text x="{LEFT}" y="{top2 + PANEL_H + 20}" font-size="11">epoch [s] 0 .. {len(new) - 1}</text>')
    legend_y = top2 + PANEL_H + 40
    for i, (color, text) in enumerate((("red", "smoother_ins, readings in the axes at the interval's start"),
                                       ("blue", "smoother_ins, readings at the interval's mid attitude"),
                                       ("green", "ekf_ins (bias panel)"))):
        parts.append(f'<text x="{LEFT + 250 * i}" y="{legend_y}" font-size="10" fill="{color}">{text}</text>')
    parts.append("</svg>")
    with open(out_path, "w") as f:
        f.write("\n".join(parts) + "\n")


if __name__ == "__main__":
    main()

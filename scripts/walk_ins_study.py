#!/usr/bin/env python3
"""The u-blox walk with its IMU: GNSS/INS (ppp_solve --estimator ekf_ins) against
GNSS-only (--estimator ekf), both broadcast-only PPP from gnss_1730.ubx, compared with
the walk's RTK reference gnss_1730_sf.pos at its fixed epochs (Q=1):

  - horizontal velocity RMS: ekf_ins its filter velocity (the attitude file), ekf the
    central difference of its positions (it has no velocity state), against the reference's
    velocity columns (which are the receiver's own NAV-PVT velocity);
  - the velocity averaged over 1 s windows against the displacement of the fixed RTK
    positions over the window (a reference independent of the receiver's velocity); ekf_ins's
    velocity is the IMU origin's, so the lever arm's change over the window is added (the
    antenna's displacement);
  - heading: ekf_ins its heading (the body x axis) against the reference's course over
    ground where the reference moves faster than 0.5 m/s; ekf the course of its velocity;
  - a GNSS gap (--gnss-gap, default 15 s mid-walk): the horizontal displacement of the
    antenna from the last epoch before the gap to the last epoch in it, against the
    reference's over the same epochs (ekf_ins coasts; ekf has no solution there).

Usage: walk_ins_study.py [--bin DIR] [--data DIR] [--out DIR] [--gap-start "HH:MM:SS"]
                         [--gap-s S] [--imu-grade G] [--doppler on|off]
                         [--estimator ekf_ins|smoother_ins]
--estimator smoother_ins measures the GNSS/INS smoother's filtered states (its attitude
file) in place of ekf_ins.
The mounting is the data set's (shared/data/README.md, ubx/): IMU 0.05 m east of the
antenna in the body frame (lever arm antenna - IMU = 0,-0.05,0 m), IMU axes rotated
roll 180, pitch 0, yaw -90 deg from the body's. doc/studies/ins_walk.md has the figures.
"""
import argparse
import math
import os
import subprocess
import sys

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATE = "2025/08/28"
WGS84_A = 6378137.0
WGS84_F = 1.0 / 298.257223563


# ---- reading ---------------------------------------------------------------------------

def seconds_of_day(hms):
    h, m, s = hms.split(":")
    return int(h) * 3600 + int(m) * 60 + float(s)


def read_reference(path):
    """RTKLIB .pos with velocities: rows (t [s of day], lat, lon, h, Q, vn, ve, vu)."""
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("%") or not line.strip():
                continue
            c = line.split()
            rows.append([seconds_of_day(c[1]), float(c[2]), float(c[3]), float(c[4]), int(float(c[5])),
                         float(c[15]), float(c[16]), float(c[17])])
    return np.array(rows)


def read_attitude(path):
    """ekf_ins attitude file: dict of columns (time as s of day; status as text)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    cols = {}
    for i, name in enumerate(header):
        values = [r[i] for r in rows]
        if name == "time_gpst":
            cols[name] = np.array([seconds_of_day(v.split("T")[1]) for v in values])
        elif name in ("status", "alignment", "doppler_update"):
            cols[name] = np.array(values)
        else:
            cols[name] = np.array([float(v) if v else math.nan for v in values])
    return cols


def read_solution_csv(path):
    """The EKF's solution CSV: (t [s of day], ECEF x, y, z) of the solved epochs."""
    out = []
    with open(path) as f:
        header = f.readline().strip().split(",")
        it, ix = header.index("time_gpst"), header.index("x_m")
        for line in f:
            c = line.strip().split(",")
            if c[ix]:
                out.append([seconds_of_day(c[it].split("T")[1]), float(c[ix]), float(c[ix + 1]), float(c[ix + 2])])
    return np.array(out)


# ---- geometry --------------------------------------------------------------------------

def geodetic_to_ecef(lat_deg, lon_deg, h_m):
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    e2 = WGS84_F * (2 - WGS84_F)
    n = WGS84_A / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    return np.stack([(n + h_m) * np.cos(lat) * np.cos(lon), (n + h_m) * np.cos(lat) * np.sin(lon),
                     (n * (1 - e2) + h_m) * np.sin(lat)], axis=-1)


def ecef_to_ne(d_ecef, lat_deg, lon_deg):
    """North and east components of ECEF vectors at a latitude and longitude."""
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    north = np.array([-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)])
    east = np.array([-math.sin(lon), math.cos(lon), 0.0])
    return np.stack([d_ecef @ north, d_ecef @ east], axis=-1)


def wrap_deg(a):
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


def match(times, ref_t, tol_s=0.06):
    """Index into ref_t of the reference epoch within tol_s of each time (-1: none)."""
    idx = np.searchsorted(ref_t, times)
    out = np.full(len(times), -1)
    for k, t in enumerate(times):
        for j in (idx[k] - 1, idx[k]):
            if 0 <= j < len(ref_t) and abs(ref_t[j] - t) <= tol_s:
                out[k] = j
    return out


def central_velocity_ne(sol, lat_deg, lon_deg, max_step_s=0.3):
    """(t, vn, ve) of a position series by central differences of neighbours <= max_step_s apart."""
    rows = []
    for k in range(1, len(sol) - 1):
        dt = sol[k + 1, 0] - sol[k - 1, 0]
        if dt <= 2 * max_step_s and sol[k, 0] - sol[k - 1, 0] <= max_step_s:
            v = ecef_to_ne((sol[k + 1, 1:4] - sol[k - 1, 1:4]) / dt, lat_deg, lon_deg)
            rows.append([sol[k, 0], v[0], v[1]])
    return np.array(rows)


def velocity_and_heading(t, vn, ve, heading_deg, ref, min_speed_mps=0.5):
    """Horizontal velocity RMS [m/s] at fixed reference epochs, and heading error RMS and
    median |error| [deg] where the reference moves faster than min_speed_mps."""
    j = match(t, ref[:, 0])
    ok = (j >= 0)
    ok[ok] &= ref[j[ok], 4] == 1
    r = ref[j[ok]]
    dv = np.hypot(vn[ok] - r[:, 5], ve[ok] - r[:, 6])
    course = np.degrees(np.arctan2(r[:, 6], r[:, 5]))
    moving = np.hypot(r[:, 5], r[:, 6]) > min_speed_mps
    err = wrap_deg(heading_deg[ok][moving] - course[moving])
    return {"n_vel": int(ok.sum()), "vel_rms": float(np.sqrt(np.mean(dv ** 2))) if ok.any() else math.nan,
            "vel_med": float(np.median(dv)) if ok.any() else math.nan,
            "n_head": int(moving.sum()),
            "head_rms": float(np.sqrt(np.mean(err ** 2))) if moving.any() else math.nan,
            "head_med": float(np.median(np.abs(err))) if moving.any() else math.nan}


def lever_arm_ne(roll_deg, pitch_deg, heading_deg, lever_arm_body_m):
    """North and east [m] of the lever arm R_ned_body l at each attitude (ZYX Euler angles of
    the attitude file: R_ned_body = Rz(heading) Ry(pitch) Rx(roll)), rows (north, east)."""
    r, p, h = (np.radians(np.asarray(a, dtype=float)) for a in (roll_deg, pitch_deg, heading_deg))
    lx, ly, lz = lever_arm_body_m
    # the first two rows of Rz Ry Rx times l
    north = (np.cos(h) * np.cos(p) * lx + (np.cos(h) * np.sin(p) * np.sin(r) - np.sin(h) * np.cos(r)) * ly
             + (np.cos(h) * np.sin(p) * np.cos(r) + np.sin(h) * np.sin(r)) * lz)
    east = (np.sin(h) * np.cos(p) * lx + (np.sin(h) * np.sin(p) * np.sin(r) + np.cos(h) * np.cos(r)) * ly
            + (np.sin(h) * np.sin(p) * np.cos(r) - np.cos(h) * np.sin(r)) * lz)
    return np.stack([north, east], axis=-1)


def window_velocity(t, vn, ve, ref, window_s=1.0, step_s=0.25, tol_s=0.06, lever_ne=None):
    """Horizontal velocity averaged over windows of window_s (trapezoid over the estimate's
    samples every step_s, all present; times within tol_s, as the attitude file's are rounded
    to 0.1 s) against the displacement of the fixed RTK positions over the same
    window divided by window_s: a velocity reference independent of the receiver's own velocity
    (the reference file's velocity columns are the receiver's NAV-PVT). RMS and median [m/s].
    The reference is the antenna's; a velocity of the IMU origin (the attitude file's) needs
    lever_ne (lever_arm_ne at each sample): the antenna moves by the IMU origin's displacement
    plus the lever arm's change over the window."""
    xyz = geodetic_to_ecef(ref[:, 1], ref[:, 2], ref[:, 3])
    samples = int(round(window_s / step_s)) + 1
    errs = []
    for k in range(len(ref)):
        k2 = np.searchsorted(ref[:, 0], ref[k, 0] + window_s - 0.01)
        if k2 >= len(ref) or abs(ref[k2, 0] - ref[k, 0] - window_s) > 0.02 or ref[k, 4] != 1 or ref[k2, 4] != 1:
            continue
        m = (t >= ref[k, 0] - tol_s) & (t <= ref[k2, 0] + tol_s)
        if m.sum() != samples or not np.all(np.isfinite(vn[m])) or not np.all(np.isfinite(ve[m])):
            continue
        est = np.array([np.trapz(vn[m], dx=step_s), np.trapz(ve[m], dx=step_s)]) / window_s
        if lever_ne is not None:
            inside = np.where(m)[0]
            est += (lever_ne[inside[-1]] - lever_ne[inside[0]]) / window_s
        truth = ecef_to_ne((xyz[k2] - xyz[k]) / window_s, ref[k, 1], ref[k, 2])
        errs.append(np.hypot(*(est - truth)))
    e = np.array(errs)
    return {"n": len(e), "rms": float(np.sqrt(np.mean(e ** 2))) if len(e) else math.nan,
            "med": float(np.median(e)) if len(e) else math.nan}


def gap_displacement(t, xyz, ref, gap_start_s, gap_s):
    """Horizontal displacement error [m] across the gap: the estimate's from the last epoch
    before the gap to the last in it, minus the reference's over the same epochs."""
    before = np.where(t < gap_start_s)[0]
    inside = np.where((t >= gap_start_s) & (t < gap_start_s + gap_s))[0]
    if not len(before) or not len(inside):
        return None
    a, b = before[-1], inside[-1]
    ja, jb = match(np.array([t[a], t[b]]), ref[:, 0])
    if ja < 0 or jb < 0:
        return None
    ref_xyz = geodetic_to_ecef(ref[[ja, jb], 1], ref[[ja, jb], 2], ref[[ja, jb], 3])
    lat, lon = ref[ja, 1], ref[ja, 2]
    d_est = ecef_to_ne(xyz[b] - xyz[a], lat, lon)
    d_ref = ecef_to_ne(ref_xyz[1] - ref_xyz[0], lat, lon)
    return {"from": t[a], "to": t[b], "ref_m": float(np.hypot(*d_ref)), "error_m": float(np.hypot(*(d_est - d_ref))),
            "fixed": bool(ref[ja, 4] == 1 and ref[jb, 4] == 1)}


# ---- running ---------------------------------------------------------------------------

def run_solve(bin_dir, data, out, name, estimator, extra):
    ubx = os.path.join(data, "streams/ubx")
    cmd = [os.path.join(bin_dir, "ppp_solve"), "--ubx", ubx + "/gnss_1730.ubx", "--nav", ubx + "/gnss_1730.ubx",
           "--atx", os.path.join(data, "antex/igs20_gps_satellites_trim.atx"),
           "--config", os.path.join(REPO, "config/live.yaml"), os.path.join(REPO, "test/rostest/live_ubx.yaml"),
           "--estimator", estimator, "--name", name, "--out", out] + extra
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode not in (0, 3):
        sys.exit("walk_ins_study: ppp_solve failed (%d):\n%s\n%s" % (done.returncode, " ".join(cmd), done.stdout))
    return " ".join(cmd)


def imu_options(data, grade, rotation, lever_arm, doppler):
    ubx = os.path.join(data, "streams/ubx")
    return ["--imu", ubx + "/imu_1730.csv", "--imu-format", "logged", "--imu-tag", ubx + "/imu_1730.csv.tag",
            "--imu-grade", grade, "--imu-rotation", rotation, "--lever-arm", lever_arm, "--doppler", doppler]


def doppler_counts(att):
    """Epochs by Doppler update outcome, and the satellites the outlier screen rejected."""
    if "doppler_update" not in att:
        return None
    outcomes = {}
    for o in att["doppler_update"]:
        outcomes[o] = outcomes.get(o, 0) + 1
    return outcomes, int(np.nansum(att["doppler_rejected"]))


def hms(s):
    return "%02d:%02d:%06.3f" % (s // 3600, (s % 3600) // 60, s % 60)


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_options(p)
    return p.parse_args(argv)


def add_options(p):
    """The study's options (also those of scripts/peers/gnss_imu_walk.py, which runs the same solutions)."""
    p.add_argument("--bin", default=os.path.join(REPO, "build_ws/devel/lib/ppp_bayes_tree"))
    p.add_argument("--data", default=os.environ.get("PPP_SHARED_DATA", os.path.join(REPO, "../shared/data")))
    p.add_argument("--out", default="/tmp/walk_ins_study")
    p.add_argument("--gap-start", default="17:31:45", help="GPST time of day of the GNSS gap's start")
    p.add_argument("--gap-s", type=float, default=15.0)
    p.add_argument("--imu-grade", default="consumer")
    p.add_argument("--imu-rotation", default="180,0,-90", help="the IMU's axes from the body's: roll,pitch,yaw [deg]")
    p.add_argument("--lever-arm", default="0,-0.05,0", help="antenna - IMU in the body frame [m]")
    p.add_argument("--doppler", default="on", choices=("on", "off"), help="ekf_ins's Doppler velocity update")
    p.add_argument("--estimator", default="ekf_ins", choices=("ekf_ins", "smoother_ins"),
                   help="the GNSS/INS estimator (smoother_ins: its filtered states; no Doppler update)")


def run_ours(a):
    """Runs ekf, the GNSS/INS estimator and it with the GNSS gap into a.out; returns the commands."""
    os.makedirs(a.out, exist_ok=True)
    gap = "%s %s,%g" % (DATE, a.gap_start, a.gap_s)
    imu = imu_options(a.data, a.imu_grade, a.imu_rotation, a.lever_arm, a.doppler)
    return [run_solve(a.bin, a.data, a.out, "walk", "ekf", []),
            run_solve(a.bin, a.data, a.out, "walk", a.estimator, imu),
            run_solve(a.bin, a.data, a.out, "walk_gap", a.estimator, imu + ["--gnss-gap", gap])]


def ours_figures(a, ref):
    """The figures of the three runs in a.out against the reference: dict with ins, gnss
    (velocity_and_heading), gap (gap_displacement of ekf_ins), and the series read."""
    lat0, lon0 = ref[0, 1], ref[0, 2]
    ins = read_attitude(os.path.join(a.out, "walk_%s_attitude.csv" % a.estimator))
    solved = ins["status"] != "no-solution"
    ins_stats = velocity_and_heading(ins["time_gpst"][solved], ins["velocity_north_mps"][solved],
                                     ins["velocity_east_mps"][solved], ins["heading_deg"][solved], ref)
    gnss = read_solution_csv(os.path.join(a.out, "walk_ekf.csv"))
    gv = central_velocity_ne(gnss, lat0, lon0)
    gnss_stats = velocity_and_heading(gv[:, 0], gv[:, 1], gv[:, 2], np.degrees(np.arctan2(gv[:, 2], gv[:, 1])), ref)
    lever = [float(x) for x in a.lever_arm.split(",")]
    ins_window = window_velocity(ins["time_gpst"], ins["velocity_north_mps"], ins["velocity_east_mps"], ref,
                                 lever_ne=lever_arm_ne(ins["roll_deg"], ins["pitch_deg"], ins["heading_deg"], lever))
    doppler_window = (window_velocity(ins["time_gpst"], ins["doppler_velocity_north_mps"],
                                      ins["doppler_velocity_east_mps"], ref)
                      if "doppler_velocity_north_mps" in ins else None)
    gnss_window = window_velocity(gv[:, 0], gv[:, 1], gv[:, 2], ref)
    gap_run = read_attitude(os.path.join(a.out, "walk_gap_%s_attitude.csv" % a.estimator))
    xyz = np.stack([gap_run["antenna_x_m"], gap_run["antenna_y_m"], gap_run["antenna_z_m"]], axis=-1)
    d = gap_displacement(gap_run["time_gpst"], xyz, ref, seconds_of_day(a.gap_start), a.gap_s)
    return {"ins": ins_stats, "gnss": gnss_stats, "gap": d, "ins_series": ins, "ins_solved": solved,
            "gnss_series": gnss, "ins_window": ins_window, "gnss_window": gnss_window,
            "doppler_window": doppler_window}



def print_table(a, f, ref):
    gnss_stats, ins_stats, d = f["gnss"], f["ins"], f["gap"]
    gnss_window, ins_window, doppler_window = f["gnss_window"], f["ins_window"], f["doppler_window"]
    print("| against the RTK reference (Q=1) | GNSS only (ekf) | GNSS/INS (%s) |" % a.estimator)
    print("|---|---|---|")
    print("| epochs compared (velocity) | %d | %d |" % (gnss_stats["n_vel"], ins_stats["n_vel"]))
    print("| horizontal velocity RMS [m/s] | %.3f | %.3f |" % (gnss_stats["vel_rms"], ins_stats["vel_rms"]))
    print("| horizontal velocity error median [m/s] | %.3f | %.3f |" % (gnss_stats["vel_med"], ins_stats["vel_med"]))
    print("| 1 s windows against the RTK displacement (all samples in) | %d | %d |" % (gnss_window["n"], ins_window["n"]))
    print("| 1 s mean velocity against the RTK displacement, RMS / median [m/s] | %.3f / %.3f | %.3f / %.3f |"
          % (gnss_window["rms"], gnss_window["med"], ins_window["rms"], ins_window["med"]))
    print("| epochs moving > 0.5 m/s | %d | %d |" % (gnss_stats["n_head"], ins_stats["n_head"]))
    print("| heading - course RMS [deg] | %.1f (course of its velocity) | %.1f |"
          % (gnss_stats["head_rms"], ins_stats["head_rms"]))
    print("| heading - course median abs [deg] | %.1f | %.1f |" % (gnss_stats["head_med"], ins_stats["head_med"]))
    own = window_velocity(ref[:, 0], ref[:, 5], ref[:, 6], ref)
    print("The reference's velocity columns (the receiver's NAV-PVT), 1 s mean against the RTK displacement:"
          " %d windows, RMS %.3f, median %.3f m/s" % (own["n"], own["rms"], own["med"]))
    if doppler_window and doppler_window["n"]:
        print("Doppler velocity alone (the least squares of ekf_ins's update), 1 s mean against the RTK displacement:"
              " %d windows, RMS %.3f, median %.3f m/s" % (doppler_window["n"], doppler_window["rms"], doppler_window["med"]))
    if d:
        print("| %g s GNSS gap %s-%s: displacement error [m] (reference moved %.2f m%s) | no solution | %.2f |"
              % (a.gap_s, hms(d["from"]), hms(d["to"]), d["ref_m"], "" if d["fixed"] else ", float ends",
                 d["error_m"]))
    else:
        print("| GNSS gap: no %s epoch before or in it | no solution | n/a |" % a.estimator)


def main():
    a = parse_args()
    commands = run_ours(a)
    ref = read_reference(os.path.join(a.data, "streams/ubx/gnss_1730_sf.pos"))
    f = ours_figures(a, ref)
    ins, solved, gnss = f["ins_series"], f["ins_solved"], f["gnss_series"]
    first_ins = ins["time_gpst"][solved][0] if solved.any() else math.nan
    print("commands:\n  " + "\n  ".join(commands))
    print("first solution: ekf %s, %s %s GPST (ephemerides first; the receiver starts 17:30:39)"
          % (hms(gnss[0, 0]), a.estimator, hms(first_ins)))
    print("aligned: %s" % (hms(ins["time_gpst"][np.argmax(ins["alignment"] == "aligned")])
                           if (ins["alignment"] == "aligned").any() else "never"))
    counts = doppler_counts(ins) if a.estimator == "ekf_ins" else None
    if counts:
        print("Doppler velocity updates (ekf_ins): %s; satellites rejected by the outlier screen: %d"
              % (", ".join("%s %d" % kv for kv in sorted(counts[0].items())), counts[1]))
    print("")
    print_table(a, f, ref)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The u-blox walk's own loosely coupled GNSS/IMU filter (rtklibexplorer's GNSS_IMU,
BSD-3-Clause) beside ours, on the same walk and the same GNSS gap, with the figures of
scripts/walk_ins_study.py (imported from it):

  - our ekf_ins and ekf (GNSS only), broadcast-only PPP from gnss_1730.ubx, run as the
    study runs them;
  - the peer on its own GNSS input: the walk's gnss_1730_sf.pos, the receiver's NAV-PVT
    RTK solution, which is also the study's reference (so its velocity and heading figures
    compare the peer with its own input);
  - the peer on our broadcast PPP (the ekf positions, as an RTKLIB .pos with velocities
    from central differences), labelled float (Q=2), as the peer knows Q 1, 2 and 5 only.

Each peer run is without a gap and with the gap's GNSS epochs removed from its input (a
temporary copy); the gap runs once with the peer's velocity matching as configured (it
corrects the coast afterwards with the first GNSS epoch after the gap) and once without it
(a forward coast, as ours). The peer is never changed in place: its src/ is copied into the
work directory, GNSS_IMU.py's data selection set to the walk as its README says (the walk's
three header lines instead of the drive's), and walk_config.py gets assignments appended
(plots off, its own simulated outages off, velocity matching off for the forward coast).

The peer needs numpy >= 2 (it joins string arrays with +, and names np.atan2); with an
older numpy (Debian 12 has 1.24) this script runs it in a process that reads string
columns as Python strings and aliases np.atan2 to np.arctan2. Nothing else is changed.

Get the peer (it is never part of this project):
    git clone https://github.com/rtklibexplorer/GNSS_IMU /path/to/GNSS_IMU
Usage: gnss_imu_walk.py --peer-dir DIR [--peer-commit SHA] [walk_ins_study.py's options]
doc/studies/ins_walk.md has the figures.
"""
import argparse
import os
import runpy
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import walk_ins_study as w  # noqa: E402

PEER_URL = "https://github.com/rtklibexplorer/GNSS_IMU"
PEER_NEEDS = ("src/GNSS_IMU.py", "src/walk_config.py", "data/walk_0827/gnss_1730_sf.pos",
              "data/walk_0827/imu_1730_sf.csv", "LICENSE")
# GNSS_IMU.py's data selection: the drive's lines, replaced by the walk's (README: "modify
# the header of the GNSS_IMU.py script to select the walking data").
DRIVE_SELECTION = ("import drive_config as cfg", "dataDir = r'..\\data\\drive_0708'", "fileIn = '1934_sf'")
PEER_Q = {"fixed": 1, "float": 2, "single": 5}
PEER_COLUMN = {"rtk": "peer on its RTK input (= the reference)", "ppp_float": "peer on our PPP (ekf) as float",
               "ppp_fixed": "peer on our PPP (ekf) labelled fixed", "ppp_single": "peer on our PPP (ekf) as single"}
UNINFORMATIVE_VELOCITY_SD_MPS = 100.0
POS_HEADER = ("%  GPST            latitude(deg) longitude(deg) height(m) Q  ns  sdn(m) sde(m) sdu(m) sdne(m) "
              "sdeu(m) sdun(m) age(s) ratio vn(m/s) ve(m/s) vu(m/s) sdvn sdve sdvu sdvne sdveu sdvun\n")


class PeerError(Exception):
    """The peer's checkout or run is not as this script expects; the text says where and why."""


# ---- the peer's checkout -----------------------------------------------------------------

def check_peer_dir(peer_dir):
    """None when peer_dir holds what the walk run needs, else the message to print."""
    missing = [p for p in PEER_NEEDS if not peer_dir or not os.path.isfile(os.path.join(peer_dir, p))]
    if missing:
        return ("gnss_imu_walk: no GNSS_IMU checkout at %s (missing %s).\n"
                "Get it with:  git clone %s DIR  and pass --peer-dir DIR"
                % (peer_dir or "(no --peer-dir given)", ", ".join(missing), PEER_URL))
    return None


def check_peer_modules():
    """None when the modules the peer imports besides numpy are there, else the message."""
    import importlib.util
    missing = [m for m in ("scipy", "matplotlib") if importlib.util.find_spec(m) is None]
    if missing:
        return ("gnss_imu_walk: the peer imports %s, missing in %s (Debian: apt-get install %s)"
                % (", ".join(missing), sys.executable, " ".join("python3-" + m for m in missing)))
    return None


def peer_commit(peer_dir, given):
    """The checkout's commit: --peer-commit when given, else git's HEAD of peer_dir."""
    if given:
        return given
    done = subprocess.run(["git", "-C", peer_dir, "rev-parse", "HEAD"], stdout=subprocess.PIPE,
                          stderr=subprocess.DEVNULL, text=True)
    return done.stdout.strip() if done.returncode == 0 else "unknown (not a git work tree; give --peer-commit)"


def select_walk(text, path, data_dir):
    """GNSS_IMU.py's text with the walk selected: each drive selection line must be there once."""
    walk = ("import walk_config as cfg", "dataDir = %r" % data_dir, "fileIn = '1730_sf'")
    lines = text.split("\n")
    for old, new in zip(DRIVE_SELECTION, walk):
        at = [i for i, line in enumerate(lines) if line.strip() == old]
        if len(at) != 1:
            raise PeerError("%s: expected the line %r once, found it %d times (the peer's data selection changed)"
                            % (path, old, len(at)))
        lines[at[0]] = new
    return "\n".join(lines)


def config_overrides(vel_match):
    """Assignments appended to the temporary walk_config.py."""
    return ("\n# appended by gnss_imu_walk.py\nplot_results = False\nplot_bias_data = False\n"
            "plot_imu_data = False\nplot_unc_data = False\n"
            "start_coast = 1e9  # its own simulated GNSS outages off\n"
            "vel_match = %s\n" % bool(vel_match))


# ---- the peer's GNSS input ---------------------------------------------------------------

def pos_time_s(line):
    """Seconds of day of an RTKLIB .pos data line ('YYYY/MM/DD HH:MM:SS.sss ...')."""
    return w.seconds_of_day(line.split()[1])


def remove_gap(lines, gap_start_s, gap_s):
    """The .pos lines without the data lines whose time is in [gap_start_s, gap_start_s + gap_s)."""
    return [x for x in lines if x.startswith("%") or not x.strip()
            or not gap_start_s <= pos_time_s(x) < gap_start_s + gap_s]


def read_ekf_csv(path):
    """ppp_solve's solution CSV, solved epochs: dict of arrays t (s of day), xyz, lat, lon, h, sigma_n/e/u."""
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    col = {name: i for i, name in enumerate(header)}
    rows = [r for r in rows if r[col["x_m"]]]
    num = lambda name: np.array([float(r[col[name]]) for r in rows])  # noqa: E731
    return {"t": np.array([w.seconds_of_day(r[col["time_gpst"]].split("T")[1]) for r in rows]),
            "date": [r[col["time_gpst"]].split("T")[0].replace("-", "/") for r in rows],
            "xyz": np.stack([num("x_m"), num("y_m"), num("z_m")], axis=-1), "lat": num("lat_deg"),
            "lon": num("lon_deg"), "h": num("height_m"), "sn": num("sigma_n_m"), "se": num("sigma_e_m"),
            "su": num("sigma_u_m")}


def ppp_as_peer_input(sol, q, vel_sd_mps=None, max_step_s=0.3):
    """RTKLIB .pos lines for the peer from our solution: positions and sigmas as solved,
    velocity the central difference of the neighbours (sigma vel_sd_mps, or when None from
    the neighbours' sigmas taken as independent), or 0 with an uninformative sigma where an
    epoch has no neighbours within max_step_s."""
    lines = [POS_HEADER]
    n = len(sol["t"])
    for k in range(n):
        vn = ve = 0.0
        sdv = UNINFORMATIVE_VELOCITY_SD_MPS
        if 0 < k < n - 1 and sol["t"][k] - sol["t"][k - 1] <= max_step_s and sol["t"][k + 1] - sol["t"][k] <= max_step_s:
            dt = sol["t"][k + 1] - sol["t"][k - 1]
            vn, ve = w.ecef_to_ne((sol["xyz"][k + 1] - sol["xyz"][k - 1]) / dt, sol["lat"][k], sol["lon"][k])
            sigma = np.hypot([sol["sn"][k - 1], sol["se"][k - 1]], [sol["sn"][k + 1], sol["se"][k + 1]])
            sdv = float(np.max(sigma)) / dt if vel_sd_mps is None else vel_sd_mps
        lines.append("%s %s %.9f %.9f %.4f %d 0 %.4f %.4f %.4f 0 0 0 0 0 %.4f %.4f 0 %.4f %.4f %.4f 0 0 0\n"
                     % (sol["date"][k], w.hms(sol["t"][k]), sol["lat"][k], sol["lon"][k], sol["h"][k], q,
                        sol["sn"][k], sol["se"][k], sol["su"][k], vn, ve, sdv, sdv, sdv))
    return lines


# ---- running the peer ----------------------------------------------------------------------

def prepare_run(peer_dir, work, name, gnss_lines, vel_match):
    """A work directory name/ with a copy of the peer's src/ set to the walk, and data/ with
    the GNSS input given and a link to the peer's walk IMU file; returns (src, data) paths."""
    run = os.path.join(work, name)
    src, data = os.path.join(run, "src"), os.path.join(run, "data")
    shutil.rmtree(run, ignore_errors=True)
    shutil.copytree(os.path.join(peer_dir, "src"), src)
    os.makedirs(data)
    main = os.path.join(src, "GNSS_IMU.py")
    with open(main) as f:
        text = select_walk(f.read(), os.path.join(peer_dir, "src/GNSS_IMU.py"), data)
    with open(main, "w") as f:
        f.write(text)
    with open(os.path.join(src, "walk_config.py"), "a") as f:
        f.write(config_overrides(vel_match))
    with open(os.path.join(data, "gnss_1730_sf.pos"), "w") as f:
        f.writelines(gnss_lines)
    os.symlink(os.path.abspath(os.path.join(peer_dir, "data/walk_0827/imu_1730_sf.csv")),
               os.path.join(data, "imu_1730_sf.csv"))
    return src, data


def run_peer(src, data):
    """Runs the prepared peer (this script's --exec-peer) and returns its output .pos path."""
    log = os.path.join(os.path.dirname(src), "peer.log")
    env = dict(os.environ, MPLBACKEND="Agg")
    with open(log, "w") as f:
        done = subprocess.run([sys.executable, os.path.abspath(__file__), "--exec-peer", src], stdout=f,
                              stderr=subprocess.STDOUT, env=env)
    out = os.path.join(data, "gnss_imu_1730_sf.pos")
    if done.returncode != 0 or not os.path.isfile(out):
        with open(log, errors="replace") as f:
            tail = f.read().replace("\r", "\n").strip().split("\n")[-12:]
        raise PeerError("the peer failed (exit %d, log %s):\n%s" % (done.returncode, log, "\n".join(tail)))
    return out


def exec_peer(src):
    """Runs src/GNSS_IMU.py in this process, with numpy 2's behaviours it uses on numpy 1."""
    if int(np.__version__.split(".")[0]) < 2:
        plain = np.genfromtxt

        def genfromtxt(*args, **kwargs):  # string columns as Python strings: + joins them
            table = plain(*args, **kwargs)
            return table.astype(object) if kwargs.get("dtype") is str else table
        np.genfromtxt = genfromtxt
        np.atan2 = np.arctan2
    sys.path.insert(0, src)
    os.chdir(src)
    runpy.run_path("GNSS_IMU.py", run_name="__main__")


# ---- the peer's output and its figures ----------------------------------------------------

def read_peer_output(path):
    """The peer's output .pos (a row per IMU epoch): dict t (s of day), lat, lon, h (deg, m),
    vn, ve (m/s), yaw_deg (its body x axis from north), coast (its Q - 1)."""
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            c = line.split()
            if line.startswith("%") or not c:
                continue
            if len(c) < 27:
                raise PeerError("%s:%d: %d fields, expected 27 (time, 25 values)" % (path, number, len(c)))
            rows.append([w.seconds_of_day(c[1])] + [float(c[i]) for i in (2, 3, 4, 5, 15, 16, 26)])
    a = np.array(rows).reshape(-1, 8)
    return {"t": a[:, 0], "lat": a[:, 1], "lon": a[:, 2], "h": a[:, 3], "coast": a[:, 4] - 1,
            "vn": a[:, 5], "ve": a[:, 6], "yaw_deg": np.degrees(a[:, 7])}


def at_epochs(series, times, tol_s=0.01):
    """The series' samples nearest to each of times (within tol_s), as a dict of arrays."""
    t = series["t"]
    j = np.clip(np.searchsorted(t, times), 1, len(t) - 1)
    j = np.where(np.abs(t[j - 1] - times) <= np.abs(t[j] - times), j - 1, j)
    keep = np.abs(t[j] - times) <= tol_s
    return {k: v[j[keep]] for k, v in series.items()}


def peer_figures(out_path, ref, times, gap_start_s, gap_s):
    """velocity_and_heading and gap_displacement of a peer run, on its samples nearest the
    given reference epochs."""
    s = at_epochs(read_peer_output(out_path), times)
    xyz = w.geodetic_to_ecef(s["lat"], s["lon"], s["h"])
    return {"vel": w.velocity_and_heading(s["t"], s["vn"], s["ve"], s["yaw_deg"], ref),
            "gap": w.gap_displacement(s["t"], xyz, ref, gap_start_s, gap_s)}


# ---- the comparison --------------------------------------------------------------------------

def peer_runs(a, work, inputs):
    """Each input (name -> .pos lines) without gap, with the gap (velocity matching as
    configured) and with the gap as a forward coast: dict (input, run) -> output path."""
    gap_start_s = w.seconds_of_day(a.gap_start)
    outputs = {}
    for name, lines in inputs.items():
        gapped = remove_gap(lines, gap_start_s, a.gap_s)
        for run, gnss, vel_match in (("nogap", lines, True), ("gap", gapped, True), ("gap_forward", gapped, False)):
            src, data = prepare_run(a.peer_dir, work, "%s_%s" % (name, run), gnss, vel_match)
            outputs[(name, run)] = run_peer(src, data)
    return outputs


def first_data_time(lines):
    return next(pos_time_s(x) for x in lines if not x.startswith("%") and x.strip())


def cell(value, fmt):
    return "n/a" if value is None or value != value else fmt % value


def print_table(a, ours, peer):
    """peer: input name -> {"vel", "gap", "gap_vm"} figures."""
    names = list(peer)
    print("| against the RTK reference (Q=1) | ours GNSS/INS (ekf_ins) | ours GNSS only (ekf) | %s |"
          % " | ".join(PEER_COLUMN[n] for n in names))
    print("|---" * (3 + len(names)) + "|")
    for part, label in (("vel", "from its first GNSS epoch"), ("vel_common", "at ekf_ins's compared epochs")):
        cols = [ours["ins"], ours["gnss"] if part == "vel" else {}] + [peer[n][part] for n in names]
        for row, key, fmt in (("epochs compared (velocity)", "n_vel", "%d"),
                              ("horizontal velocity RMS [m/s]", "vel_rms", "%.3f"),
                              ("horizontal velocity error median [m/s]", "vel_med", "%.3f"),
                              ("epochs moving > 0.5 m/s", "n_head", "%d"),
                              ("heading - course RMS [deg]", "head_rms", "%.1f"),
                              ("heading - course median abs [deg]", "head_med", "%.1f")):
            print("| %s, %s | %s |" % (row, label, " | ".join(cell(c.get(key), fmt) for c in cols)))
    err = lambda d: d["error_m"] if d else None  # noqa: E731
    d = ours["gap"] or next((peer[n]["gap"] for n in names if peer[n]["gap"]), None)
    moved = " (reference moved %.2f m)" % d["ref_m"] if d else ""
    print("| %g s GNSS gap from %s, forward coast: displacement error [m]%s | %s | no solution | %s |"
          % (a.gap_s, a.gap_start, moved, cell(err(ours["gap"]), "%.2f"),
             " | ".join(cell(err(peer[n]["gap"]), "%.2f") for n in names)))
    print("| the same gap, the peer's velocity matching on (corrected with the first GNSS epoch after it) "
          "| n/a | n/a | %s |" % " | ".join(cell(err(peer[n]["gap_vm"]), "%.2f") for n in names))


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    w.add_options(p)
    p.add_argument("--peer-dir", help="a checkout of " + PEER_URL)
    p.add_argument("--ppp-vel-sd", type=float, metavar="M/S",
                   help="the velocity sigma given with our PPP (default: from the neighbours' position sigmas)")
    p.add_argument("--peer-commit", help="the checkout's commit, when it is not a git work tree")
    p.add_argument("--ppp-q", default="float,fixed",
                   help="comma list of the solution states (%s) our PPP is given as in the peer's input, "
                        "a peer column each (its noise gain; yaw alignment and velocity matching need fixed)"
                        % "|".join(sorted(PEER_Q)))
    a = p.parse_args(argv)
    a.out = os.path.abspath(a.out)
    a.work = os.path.join(a.out, "gnss_imu_peer")
    a.ppp_q = a.ppp_q.split(",") if a.ppp_q else []
    unknown = [q for q in a.ppp_q if q not in PEER_Q]
    if unknown:
        p.error("--ppp-q: unknown state %s (known: %s)" % (", ".join(unknown), ", ".join(sorted(PEER_Q))))
    return a


def main(argv=None):
    if argv is None and len(sys.argv) == 3 and sys.argv[1] == "--exec-peer":
        exec_peer(sys.argv[2])
        return 0
    a = parse_args(argv)
    problem = check_peer_dir(a.peer_dir) or check_peer_modules()
    if problem:
        print(problem, file=sys.stderr)
        return 2
    try:
        return compare(a)
    except PeerError as e:
        print("gnss_imu_walk: %s" % e, file=sys.stderr)
        return 1


def compare(a):
    commands = w.run_ours(a)
    ref_path = os.path.join(a.data, "streams/ubx/gnss_1730_sf.pos")
    ref = w.read_reference(ref_path)
    ours = w.ours_figures(a, ref)
    with open(os.path.join(a.peer_dir, "data/walk_0827/gnss_1730_sf.pos")) as f:
        rtk_lines = f.readlines()
    with open(ref_path) as f:
        same = f.readlines() == rtk_lines
    ekf = read_ekf_csv(os.path.join(a.out, "walk_ekf.csv"))
    inputs = {"rtk": rtk_lines}
    inputs.update({"ppp_" + q: ppp_as_peer_input(ekf, PEER_Q[q], a.ppp_vel_sd) for q in a.ppp_q})
    outputs = peer_runs(a, a.work, inputs)
    gap_start_s = w.seconds_of_day(a.gap_start)
    j = w.match(ours["ins_series"]["time_gpst"][ours["ins_solved"]], ref[:, 0])
    common = ref[j[j >= 0], 0]
    peer = {}
    for name, lines in inputs.items():
        times = ref[ref[:, 0] >= first_data_time(lines) - 0.01, 0]
        fig = lambda run, t: peer_figures(outputs[(name, run)], ref, t, gap_start_s, a.gap_s)  # noqa: E731
        peer[name] = {"vel": fig("nogap", times)["vel"], "vel_common": fig("nogap", common)["vel"],
                      "gap": fig("gap_forward", times)["gap"], "gap_vm": fig("gap", times)["gap"]}
    print("commands (ours):\n  " + "\n  ".join(commands))
    print("peer: %s at commit %s (%s), BSD-3-Clause; run from copies in %s"
          % (PEER_URL, peer_commit(a.peer_dir, a.peer_commit), a.peer_dir, a.work))
    print("peer's GNSS input gnss_1730_sf.pos is %s the reference file %s"
          % ("the same as" if same else "NOT the same as", ref_path))
    print("peer on our PPP: the %d solved epochs of walk_ekf.csv, given as %s; velocity sigma %s"
          % (len(ekf["t"]), ", ".join("Q=%d (%s)" % (PEER_Q[q], q) for q in a.ppp_q),
             "from the position sigmas" if a.ppp_vel_sd is None else "%g m/s" % a.ppp_vel_sd))
    print("")
    print_table(a, ours, peer)
    return 0


if __name__ == "__main__":
    sys.exit(main())

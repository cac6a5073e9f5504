#!/usr/bin/env python3
"""Unit test of scripts/peers/gnss_imu_walk.py without the peer: its refusal of a missing
checkout, the walk selection in the peer's header, the gap removal, our PPP written as the
peer's input, and the peer's output read and measured, on series whose velocities, headings
and displacements are known by construction (a walk east at 1 m/s along the equator)."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "peers", "gnss_imu_walk.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import gnss_imu_walk as g  # noqa: E402

w = g.w
T0 = 60000.0  # 16:40:00


def reference(n=80, dt=0.25):
    """Rows (t, lat, lon, h, Q, vn, ve, vu): east at 1 m/s along the equator, fixed."""
    t = T0 + dt * np.arange(n)
    return np.stack([t, np.zeros(n), np.degrees((t - T0) / w.WGS84_A), np.zeros(n), np.ones(n), np.zeros(n),
                     np.ones(n), np.zeros(n)], axis=-1)


def pos_line(t, fields):
    return "2025/08/28 %s %s\n" % (w.hms(t), " ".join("%.7f" % v for v in fields))


def peer_output(path, drift_from_s=None, dt=0.01, n=2000, vn_error=0.03, yaw_deg=100.0):
    """A peer output file (time + 25 values a row): the walk east, north velocity off by
    vn_error, yaw yaw_deg, and from drift_from_s on a position drifting north at 0.1 m/s."""
    with open(path, "w") as f:
        f.write("%  GPST latitude(deg) ...\n")
        for t in T0 + dt * np.arange(n):
            north_m = 0.1 * (t - drift_from_s) if drift_from_s is not None and t >= drift_from_s else 0.0
            v = [0.0] * 25
            v[0], v[1], v[3] = np.degrees(north_m / w.WGS84_A), np.degrees((t - T0) / w.WGS84_A), 1.0
            v[13], v[14], v[24] = vn_error, 1.0, np.radians(yaw_deg)
            f.write(pos_line(t, v))


class PeerDirTest(unittest.TestCase):
    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True)

    def test_missing_checkout_is_refused_with_the_clone_command(self):
        for args in (["--peer-dir", "/nonexistent/GNSS_IMU"], []):
            done = self.run_script(*args)
            self.assertEqual(done.returncode, 2, done.stderr)
            self.assertIn("git clone https://github.com/rtklibexplorer/GNSS_IMU", done.stderr)
            self.assertIn("missing src/GNSS_IMU.py", done.stderr)
            self.assertEqual(done.stdout, "")

    def test_partial_checkout_names_what_is_missing(self):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "src"))
            open(os.path.join(d, "src", "GNSS_IMU.py"), "w").close()
            message = g.check_peer_dir(d)
            self.assertIn("data/walk_0827/imu_1730_sf.csv", message)
            self.assertNotIn("src/GNSS_IMU.py,", message)
            for p in g.PEER_NEEDS:
                os.makedirs(os.path.dirname(os.path.join(d, p)), exist_ok=True)
                open(os.path.join(d, p), "w").close()
            self.assertIsNone(g.check_peer_dir(d))

    def test_unknown_ppp_state_is_an_error(self):
        done = self.run_script("--peer-dir", "/nonexistent", "--ppp-q", "float,rtk")
        self.assertEqual(done.returncode, 2)
        self.assertIn("unknown state rtk", done.stderr)


class InputTest(unittest.TestCase):
    HEADER = ("# import walk_config as cfg\n# dataDir = r'..\\data\\walk_0827'\n# fileIn = '1730_sf'\n\n"
              "import drive_config as cfg\ndataDir = r'..\\data\\drive_0708'\nfileIn = '1934_sf'\nrest = 1\n")

    def test_select_walk(self):
        text = g.select_walk(self.HEADER, "GNSS_IMU.py", "/tmp/run/data")
        lines = text.split("\n")
        self.assertEqual(lines[:3], self.HEADER.split("\n")[:3])  # the comments stay
        self.assertEqual(lines[4:8], ["import walk_config as cfg", "dataDir = '/tmp/run/data'", "fileIn = '1730_sf'",
                                      "rest = 1"])

    def test_select_walk_refuses_a_changed_header(self):
        with self.assertRaises(g.PeerError) as e:
            g.select_walk(self.HEADER.replace("fileIn = '1934_sf'", "fileIn = '2000_sf'"), "x/GNSS_IMU.py", "/d")
        self.assertIn("x/GNSS_IMU.py", str(e.exception))
        self.assertIn("fileIn = '1934_sf'", str(e.exception))

    def test_config_overrides(self):
        namespace = {}
        exec(g.config_overrides(False), namespace)
        self.assertFalse(namespace["vel_match"])
        self.assertFalse(namespace["plot_results"])
        self.assertGreater(namespace["start_coast"], 1e6)

    def test_remove_gap(self):
        lines = ["% header\n"] + [pos_line(T0 + 0.25 * k, [0.0] * 22) for k in range(20)]
        kept = g.remove_gap(lines, T0 + 1.0, 2.0)  # removes 1.0, 1.25, ..., 2.75
        self.assertEqual(kept[0], "% header\n")
        times = [g.pos_time_s(x) - T0 for x in kept[1:]]
        self.assertEqual(times, [0.0, 0.25, 0.5, 0.75, 3.0, 3.25, 3.5, 3.75, 4.0, 4.25, 4.5, 4.75])

    def test_ppp_as_peer_input(self):
        t = T0 + 0.25 * np.array([0, 1, 2, 3, 5])  # a missing epoch before the last
        lon = np.degrees((t - T0) / w.WGS84_A)
        sol = {"t": t, "date": ["2025/08/28"] * 5, "xyz": w.geodetic_to_ecef(np.zeros(5), lon, np.zeros(5)),
               "lat": np.zeros(5), "lon": lon, "h": np.zeros(5), "sn": np.full(5, 1.0), "se": np.full(5, 0.5),
               "su": np.full(5, 2.0)}
        lines = g.ppp_as_peer_input(sol, 2)
        self.assertTrue(lines[0].startswith("%"))
        rows = [x.split() for x in lines[1:]]
        self.assertEqual([len(r) for r in rows], [24] * 5)  # date, time and the 22 columns the peer reads
        vals = np.array([[float(v) for v in r[2:]] for r in rows])
        np.testing.assert_array_equal(vals[:, 3], 2)  # Q
        np.testing.assert_allclose(vals[1:3, 13:15], [[0.0, 1.0], [0.0, 1.0]], atol=1e-9)  # vn, ve
        self.assertAlmostEqual(vals[1, 16], np.sqrt(2.0) / 0.5, places=4)  # sigma of (x[k+1]-x[k-1])/0.5 s
        for k in (0, 3, 4):  # no neighbour on one side within 0.3 s
            self.assertEqual(list(vals[k, 13:15]), [0.0, 0.0])
            self.assertEqual(vals[k, 16], g.UNINFORMATIVE_VELOCITY_SD_MPS)
        self.assertEqual(float(g.ppp_as_peer_input(sol, 1, 2.0)[2].split()[19]), 2.0)


class OutputTest(unittest.TestCase):
    def test_read_and_measure(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "gnss_imu_1730_sf.pos")
            gap_start, gap_s = T0 + 5.0, 10.0
            peer_output(path, drift_from_s=gap_start)
            ref = reference()
            f = g.peer_figures(path, ref, ref[:, 0], gap_start, gap_s)
        self.assertEqual(f["vel"]["n_vel"], len(ref))
        self.assertAlmostEqual(f["vel"]["vel_rms"], 0.03, places=6)
        self.assertAlmostEqual(f["vel"]["head_med"], 10.0, places=4)
        # From the last epoch before the gap (T0+4.75) to the last in it (T0+14.75): 1.0 m north too much.
        self.assertAlmostEqual(f["gap"]["to"] - T0, 14.75, places=6)
        self.assertAlmostEqual(f["gap"]["error_m"], 0.1 * 9.75, delta=0.02)  # lat written with 7 decimals

    def test_at_epochs_takes_the_nearest_within_tolerance(self):
        series = {"t": np.array([0.0, 0.006, 0.013, 0.5]), "v": np.array([1.0, 2.0, 3.0, 4.0])}
        got = g.at_epochs(series, np.array([0.004, 0.011, 0.25, 0.495]))
        np.testing.assert_array_equal(got["v"], [2.0, 3.0, 4.0])

    def test_short_line_is_reported_with_its_place(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "out.pos")
            with open(path, "w") as f:
                f.write("% h\n" + pos_line(T0, [0.0] * 25) + pos_line(T0 + 1, [0.0] * 20))
            with self.assertRaises(g.PeerError) as e:
                g.read_peer_output(path)
        self.assertIn("out.pos:3: 22 fields, expected 27", str(e.exception))


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/env python3
"""Unit test of scripts/walk_ins_study.py on small series whose velocities, courses and
displacements are known by construction (a walk east at 1 m/s along the equator)."""
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import walk_ins_study as w  # noqa: E402


def reference(n=40, dt=0.25, speed=1.0, q=1):
    """Rows (t, lat, lon, h, Q, vn, ve, vu): east at `speed` along the equator from 0 deg."""
    t = 60000.0 + dt * np.arange(n)
    lon = np.degrees(speed * (t - t[0]) / w.WGS84_A)
    return np.stack([t, np.zeros(n), lon, np.zeros(n), np.full(n, q), np.zeros(n), np.full(n, speed), np.zeros(n)],
                    axis=-1)


class WalkInsStudyTest(unittest.TestCase):
    def test_wrap_and_match(self):
        np.testing.assert_allclose(w.wrap_deg([190.0, -190.0, 10.0]), [-170.0, 170.0, 10.0])
        ref_t = np.array([0.0, 0.25, 0.5])
        np.testing.assert_array_equal(w.match(np.array([0.24, 0.6, 0.45]), ref_t), [1, -1, 2])

    def test_velocity_and_heading(self):
        ref = reference()
        t = ref[:, 0]
        # 0.03 m/s north error everywhere; heading 10 deg off the course (90 deg) on every epoch.
        stats = w.velocity_and_heading(t, np.full(len(t), 0.03), np.ones(len(t)), np.full(len(t), 100.0), ref)
        self.assertEqual(stats["n_vel"], len(t))
        self.assertAlmostEqual(stats["vel_rms"], 0.03, places=12)
        self.assertAlmostEqual(stats["head_rms"], 10.0, places=9)
        self.assertAlmostEqual(stats["head_med"], 10.0, places=9)
        # Float reference epochs (Q=2) are left out.
        self.assertEqual(w.velocity_and_heading(t, np.zeros(len(t)), np.ones(len(t)), np.zeros(len(t)),
                                                reference(q=2))["n_vel"], 0)

    def test_central_velocity_and_gap(self):
        ref = reference()
        xyz = w.geodetic_to_ecef(ref[:, 1], ref[:, 2], ref[:, 3])
        sol = np.column_stack([ref[:, 0], xyz])
        v = w.central_velocity_ne(sol, 0.0, 0.0)
        np.testing.assert_allclose(v[:, 1], 0.0, atol=1e-6)
        np.testing.assert_allclose(v[:, 2], 1.0, atol=1e-6)
        # A 2 s gap from t0 + 2 s: the reference moves between the last epoch before
        # it (1.75 s) and the last in it (3.75 s), 2 m; an estimate 0.3 m short along the track has that error.
        t = ref[:, 0]
        est = xyz.copy()
        inside = (t >= t[0] + 2.0) & (t < t[0] + 4.0)
        est[np.where(inside)[0][-1]] -= np.array([0.0, 0.3, 0.0])  # ECEF y is east at longitude 0
        d = w.gap_displacement(t, est, ref, t[0] + 2.0, 2.0)
        self.assertAlmostEqual(d["ref_m"], 2.0, places=4)
        self.assertAlmostEqual(d["error_m"], 0.3, places=4)
        self.assertTrue(d["fixed"])
        self.assertIsNone(w.gap_displacement(t, est, ref, t[0] - 10.0, 2.0))

    def test_reads_the_reference_columns(self):
        path = os.path.join(os.environ.get("TMPDIR", "/tmp"), "walk_ins_study_ref.pos")
        with open(path, "w") as f:
            f.write("%  GPST  latitude(deg) ...\n")
            f.write("2025/08/28 17:30:44.999 40.0966916 -105.1471664 1601.4460000 1.0000000 25.0000000 0.0098995 "
                    "0.0098995 0.0100000 0.0000000 0.0000000 0.0000000 0.0000000 0.0000000 0.0120000 -0.0040000 "
                    "-0.0110000 0.0558614 0.0558614 0.0558614 0.0000000 0.0000000 0.0000000\n")
        ref = w.read_reference(path)
        np.testing.assert_allclose(ref[0], [17 * 3600 + 30 * 60 + 44.999, 40.0966916, -105.1471664, 1601.446, 1,
                                            0.012, -0.004, -0.011])
        os.remove(path)

    def test_window_velocity_against_the_rtk_displacement(self):
        ref = reference()  # east at 1 m/s, 4 Hz
        t = ref[:, 0]
        exact = w.window_velocity(t, np.zeros(len(t)), np.ones(len(t)), ref)
        self.assertEqual(exact["n"], len(t) - 4)
        self.assertLess(exact["rms"], 1e-3)
        # 0.3 m/s north and 0.4 m/s east too much: 0.5 m/s in every window
        off = w.window_velocity(t, np.full(len(t), 0.3), np.full(len(t), 1.4), ref)
        self.assertAlmostEqual(off["rms"], 0.5, places=3)
        self.assertAlmostEqual(off["med"], 0.5, places=3)
        # a window missing a sample is left out
        self.assertEqual(w.window_velocity(np.delete(t, 10), np.zeros(len(t) - 1), np.ones(len(t) - 1), ref)["n"],
                         len(t) - 4 - 5)

    def test_window_velocity_of_the_antenna_from_the_imu_origin(self):
        # The IMU origin at rest, the body turning at 1 rad/s about down: the antenna 0.05 m to the
        # body's left (lever arm (0, -0.05, 0)) goes round it; the reference is the antenna's.
        t = 60000.0 + 0.25 * np.arange(40)
        heading_deg = np.degrees(1.0 * (t - t[0]))
        lever = w.lever_arm_ne(np.zeros(len(t)), np.zeros(len(t)), heading_deg, (0.0, -0.05, 0.0))
        np.testing.assert_allclose(lever[0], [0.0, -0.05], atol=1e-12)
        np.testing.assert_allclose(lever[6], [0.05 * math.sin(1.5), -0.05 * math.cos(1.5)], atol=1e-12)
        ref = reference()
        meridian_radius_m = w.WGS84_A * (1 - w.WGS84_F * (2 - w.WGS84_F))  # at the equator
        ref[:, 1] = np.degrees(lever[:, 0] / meridian_radius_m)  # the antenna's north and east along the equator
        ref[:, 2] = np.degrees(lever[:, 1] / w.WGS84_A)
        zeros = np.zeros(len(t))
        self.assertLess(w.window_velocity(t, zeros, zeros, ref, lever_ne=lever)["rms"], 1e-6)  # 2e-4 with a sphere's radius
        # the IMU origin's velocity taken as the antenna's: the chord of 1 rad of the 0.05 m circle per second
        self.assertAlmostEqual(w.window_velocity(t, zeros, zeros, ref)["rms"], 2 * 0.05 * math.sin(0.5), places=6)

    def test_reads_the_doppler_columns_of_the_attitude_file(self):
        path = os.path.join(os.environ.get("TMPDIR", "/tmp"), "walk_ins_study_attitude.csv")
        with open(path, "w") as f:
            f.write("time_gpst,status,velocity_north_mps,alignment,doppler_update,doppler_satellites,doppler_rejected\n")
            f.write("2025-08-28T17:31:25.2,ppp-float,0.5,level_only,applied,8,1\n")
            f.write("2025-08-28T17:31:25.4,no-solution,0.6,aligned,innovation_refused,7,0\n")
            f.write("2025-08-28T17:31:25.6,ppp-float,0.7,aligned,applied,9,2\n")
        att = w.read_attitude(path)
        self.assertEqual(list(att["doppler_update"]), ["applied", "innovation_refused", "applied"])
        outcomes, rejected = w.doppler_counts(att)
        self.assertEqual(outcomes, {"applied": 2, "innovation_refused": 1})
        self.assertEqual(rejected, 3)
        self.assertIsNone(w.doppler_counts({"time_gpst": att["time_gpst"]}))  # a file without the columns
        os.remove(path)


if __name__ == "__main__":
    unittest.main()

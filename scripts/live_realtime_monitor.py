#!/usr/bin/env python3
# Observer of a live run for scripts/bench_live_realtime.sh ("no dropped
# epochs at 10 Hz real-time speed"; prints figures, asserts nothing). Run with
# /usr/bin/python3 (ROS modules) after sourcing build_ws/devel/setup.bash.
#
# Listens, without changing anything, to:
#   - the raw receiver topic (rtcm_msgs/Message from ppp_stream_node, read as raw
#     bytes: rospy.AnyMsg): the observation epochs on the wire (distinct MSM epoch
#     times) and, per epoch, header.stamp of its last MSM frame = the wall time the
#     transport read it (for a real receiver: its output time);
#   - <ns>/ppp/status of each PPP node: solutions out, their update_time_s, and the
#     end-to-end latency = wall time the status arrives here - the epoch's last
#     frame stamp above (transport + node decoding + waiting + estimator + publish);
#   - /diagnostics: the last "live streams" status of each node (input and estimator
#     CPU seconds, the node's own latency figures) and the transport node's "stream".
# On SIGINT it writes a JSON summary to --out.
#
# Matching a status to its epoch: MSM epoch times (RTCM 10403.3 DF004 GPS/Galileo/QZSS
# time of week [ms], DF427 BeiDou = GPST - 14 s, DF034 GLONASS time of day in UTC(SU)
# = UTC + 3 h) and the status stamp (UTC) are all reduced to GPS time modulo one
# hour (ms), with --leap-s (GPST - UTC: 18 s since 2017).
import argparse
import json
import signal
import struct
import threading
import time

import importlib.util
import os

import rospy


def load_ppp_status():
    """ppp_bayes_tree/PppStatus, loaded from its generated module alone: the package's
    __init__ imports every message, some of them needing geometry_msgs' Python module,
    which may be absent."""
    for base in os.environ.get("PYTHONPATH", "").split(os.pathsep):
        path = os.path.join(base, "ppp_bayes_tree", "msg", "_PppStatus.py")
        if os.path.exists(path):
            spec = importlib.util.spec_from_file_location("ppp_status_module", path)
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            return module.PppStatus
    raise ImportError("ppp_bayes_tree/msg/_PppStatus.py not on PYTHONPATH (source build_ws/devel/setup.bash; "
                      "build target ppp_bayes_tree_generate_messages_py)")


PppStatus = load_ppp_status()

HOUR_MS = 3600 * 1000


def msm_epoch_key(payload, leap_s):
    """GPST modulo one hour [ms] of an MSM frame payload, or None for other frames."""
    if len(payload) < 8:
        return None
    word = int.from_bytes(payload[:8], "big")
    msg_type = word >> 52
    epoch = (word >> (64 - 54)) & ((1 << 30) - 1)
    group = msg_type // 10 * 10
    if not (1071 <= msg_type <= 1137 and 1 <= msg_type - group <= 7):
        return None
    if group == 1080:  # GLONASS: 3 bits day of week + 27 bits time of day (UTC(SU) = UTC + 3 h)
        tod_ms = epoch & ((1 << 27) - 1)
        return (tod_ms - 3 * HOUR_MS + leap_s * 1000) % HOUR_MS
    if group == 1120:  # BeiDou: BDT = GPST - 14 s
        return (epoch + 14000) % HOUR_MS
    return epoch % HOUR_MS


class Monitor:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.epoch_stamp = {}  # key -> wall stamp of the epoch's last MSM frame so far
        self.epoch_order = []  # keys in order of first appearance (bounded below)
        self.frames = 0
        self.seq_gaps = 0
        self.last_seq = None
        self.first_frame_wall = None
        self.last_frame_wall = None
        # Per node: (epoch key, wall time received, update_time_s, solved) of every status;
        # matched with the wire epochs at the end (a status may arrive before this
        # process has handled the frames of its epoch).
        self.statuses = {ns: [] for ns in args.nodes}
        self.diagnostics = {}
        rospy.Subscriber(args.receiver_topic, rospy.AnyMsg, self.on_frame, queue_size=10000)
        for ns in args.nodes:
            rospy.Subscriber(ns.rstrip("/") + "/ppp/status", PppStatus, self.on_status, callback_args=ns,
                             queue_size=10000)
        # diagnostic_msgs/DiagnosticArray read as raw bytes (its Python module may be absent).
        rospy.Subscriber("/diagnostics", rospy.AnyMsg, self.on_diagnostics, queue_size=100)

    def on_frame(self, msg):
        buf = msg._buff
        try:
            seq, secs, nsecs, n_id = struct.unpack_from("<IIII", buf, 0)
            off = 16 + n_id
            (n,) = struct.unpack_from("<I", buf, off)
            frame = buf[off + 4:off + 4 + n]
        except struct.error:
            return
        stamp = secs + 1e-9 * nsecs
        with self.lock:
            self.frames += 1
            if self.last_seq is not None and seq > self.last_seq + 1:
                self.seq_gaps += seq - self.last_seq - 1
            self.last_seq = seq
            now = time.time()
            if self.first_frame_wall is None:
                self.first_frame_wall = now
            self.last_frame_wall = now
            if len(frame) < 6 or frame[0] != 0xD3:
                return
            key = msm_epoch_key(frame[3:], self.args.leap_s)
            if key is None:
                return
            if key not in self.epoch_stamp:
                self.epoch_order.append(key)
                if len(self.epoch_order) > 36000:  # one hour at 10 Hz: keys repeat after an hour
                    self.epoch_stamp.pop(self.epoch_order.pop(0), None)
            self.epoch_stamp[key] = max(stamp, self.epoch_stamp.get(key, 0.0))

    def on_status(self, msg, ns):
        now = time.time()
        key = (msg.header.stamp.secs * 1000 + int(round(msg.header.stamp.nsecs * 1e-6)) +
               self.args.leap_s * 1000) % HOUR_MS
        with self.lock:
            self.statuses[ns].append((key, now, msg.update_time_s, msg.solution_state != PppStatus.NO_SOLUTION))

    def on_diagnostics(self, msg):
        # DiagnosticArray: Header (seq, stamp, frame_id), DiagnosticStatus[] (int8 level, string
        # name, message, hardware_id, KeyValue[] values (string key, value)); ROS serialization.
        buf, off = msg._buff, 0

        def u32():
            nonlocal off
            (v,) = struct.unpack_from("<I", buf, off)
            off += 4
            return v

        def text():
            nonlocal off
            n = u32()
            v = bytes(buf[off:off + n]).decode("utf-8", "replace")
            off += n
            return v

        try:
            off = 12
            text()  # frame_id
            statuses = []
            for _ in range(u32()):
                level = struct.unpack_from("<b", buf, off)[0]
                off += 1
                name, message, _hw = text(), text(), text()
                values = {}
                for _ in range(u32()):
                    k = text()
                    values[k] = text()
                statuses.append((level, name, message, values))
        except struct.error:
            return
        with self.lock:
            for level, name, message, values in statuses:
                if name.endswith("live streams") or name.endswith(": stream"):
                    self.diagnostics[name] = {"level": level, "message": message, "values": values}

    def summary(self):
        with self.lock:
            wire = set(self.epoch_stamp)
            nodes = {}
            for ns, statuses in self.statuses.items():
                keys = set(k for k, _, _, _ in statuses)
                # Epochs on the wire with no solution out, from the node's first solution on (those
                # before it went by while the node was starting: counted apart).
                first = next((i for i, k in enumerate(self.epoch_order) if k in keys), len(self.epoch_order))
                missing = [k for k in self.epoch_order[first:] if k not in keys]
                nodes[ns] = {
                    "statuses": len(statuses), "solved": sum(1 for s in statuses if s[3]),
                    "update_s": [s[2] for s in statuses],
                    # transport read of the epoch's last MSM frame -> status received here
                    "latency_s": [t - self.epoch_stamp[k] for k, t, _, _ in statuses if k in self.epoch_stamp],
                    # the same without the start-up (statuses received in the first --steady-after-s
                    # of the replay: epochs held for the first station frame 1005/1006, see the script)
                    "latency_steady_s": [t - self.epoch_stamp[k] for k, t, _, _ in statuses
                                         if k in self.epoch_stamp and self.first_frame_wall is not None
                                         and t - self.first_frame_wall > self.args.steady_after_s],
                    "not_on_wire": len(keys - wire),
                    "dropped": len(missing),
                    "before_first_solution": first,
                    "dropped_gpst_mod_hour_s": [k / 1000.0 for k in missing[:20]],
                }
            return {"frames": self.frames, "frame_seq_gaps": self.seq_gaps, "epochs_on_wire": len(wire),
                    "first_frame_wall": self.first_frame_wall, "last_frame_wall": self.last_frame_wall,
                    "nodes": nodes, "diagnostics": self.diagnostics}


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--receiver-topic", default="/gnss/receiver")
    p.add_argument("--nodes", nargs="+", default=["/ekf", "/smoother"], help="namespaces of the PPP nodes")
    p.add_argument("--leap-s", type=int, default=18, help="GPST - UTC [s]")
    p.add_argument("--steady-after-s", type=float, default=30.0,
                   help="latency_steady_s: statuses received later than this after the first frame [s]")
    p.add_argument("--out", required=True, help="JSON summary written at SIGINT")
    args = p.parse_args(rospy.myargv()[1:])
    rospy.init_node("live_realtime_monitor", disable_signals=True)
    m = Monitor(args)
    done = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: done.set())
    signal.signal(signal.SIGTERM, lambda *_: done.set())
    while not done.is_set():
        done.wait(0.2)
    with open(args.out, "w") as f:
        json.dump(m.summary(), f)
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()

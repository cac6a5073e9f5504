#!/usr/bin/env python3
# Observer of a live run for scripts/bench_live_realtime.sh (issue 14, "no dropped
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
        self.nodes = {ns: {"statuses": 0, "solved": 0, "update_s": [], "latency_s": [], "unmatched": 0,
                           "first_wall": None, "last_wall": None}
                      for ns in args.nodes}
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
            n = self.nodes[ns]
            n["statuses"] += 1
            if n["first_wall"] is None:
                n["first_wall"] = now
            n["last_wall"] = now
            if msg.solution_state != PppStatus.NO_SOLUTION:
                n["solved"] += 1
            n["update_s"].append(msg.update_time_s)
            if key in self.epoch_stamp:
                n["latency_s"].append(now - self.epoch_stamp[key])
            else:
                n["unmatched"] += 1

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
            return {"frames": self.frames, "frame_seq_gaps": self.seq_gaps, "epochs_on_wire": len(self.epoch_stamp),
                    "first_frame_wall": self.first_frame_wall, "last_frame_wall": self.last_frame_wall,
                    "nodes": self.nodes, "diagnostics": self.diagnostics}


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--receiver-topic", default="/gnss/receiver")
    p.add_argument("--nodes", nargs="+", default=["/ekf", "/smoother"], help="namespaces of the PPP nodes")
    p.add_argument("--leap-s", type=int, default=18, help="GPST - UTC [s]")
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

#!/usr/bin/env bash
# Real-time benchmark of the live path ("no dropped epochs at 10 Hz real-time
# speed", "decoding and bridge CPU under 5 % of one core at 10 Hz"): an RTCM 3 recording
# is replayed by ppp_stream_node (file://...?speed=S, paced by its MSM epoch times, as a
# receiver on a serial port would deliver it: one rtcm_msgs/Message per frame on
# /gnss/receiver) into ppp_ekf_node and ppp_smoother_node side by side in live mode
# (ros.live, each decoding through LiveGnssInput; config/ppp.yaml + config/live.yaml,
# broadcast only: the ephemerides come in the stream), as launch/live.launch example (b)
# runs them. Default: week-rollover-STR24.rtcm3 (STR2, 1 Hz, MSM4 GPS + GLONASS +
# Galileo + QZSS + BeiDou, 1,133 epochs = 18.9 min) at speed 10 = 10 epochs per second
# of wall time for 113 s.
#
# Measured (prints figures, asserts nothing):
#   - epochs on the wire (distinct MSM epoch times seen on /gnss/receiver by
#     scripts/live_realtime_monitor.py), decoded by each node (its diagnostics), solutions
#     out (ppp/status messages), dropped = on the wire - out; messages lost at a queue
#     (header.seq gaps, seen by the nodes and by the monitor);
#   - CPU of each process (/proc/PID/stat utime + stime over the replay): % of one core
#     and ms per epoch; inside the PPP nodes, thread CPU of the input (message conversion
#     + LiveGnssInput decoding) and of the estimator, from the nodes' diagnostics;
#   - the update time per epoch (PppStatus.update_time_s, wall): median/p99/max over all
#     epochs and over those after the smoother's window is full;
#   - end-to-end latency: the wall time the status arrives at the monitor minus the
#     transport's header.stamp of the epoch's last MSM frame (transport + decoding +
#     estimator + publication), median/p99/max, over all epochs and without the first 30 s
#     (start-up: the frames published before the nodes' subscriptions connect are lost,
#     among them the first station frame 1005/1006, so the first epochs wait for the next
#     one, up to 10 s: ros.live station wait, app/live_gnss_input.h); and the nodes' own
#     (subscriber callback of the epoch's last chunk -> solution published).
# Fixed lag: --lag-s (default 600 s of data time for a recording: at 10x a 1 Hz recording
# gives the smoother a window of 600 states, as config/live.yaml's 60 s at a true 10 Hz does).
#
# --simulate MIN: instead, a TRUE 10 Hz stream: a simulated flight of MIN minutes
# (ppp_bench_live_stream: MSM7 GPS L1/L2 at 10 Hz + 1005, and its constellation as a RINEX
# navigation file given to the nodes as ros.live.navigation_files), replayed at speed 1,
# with config/ppp_simulated.yaml (the simulation's physics) and config/live.yaml as is
# (fixed lag 60 s = 600 states).
#
# --config YAML (repeatable): laid over the nodes' configuration after config/live.yaml,
# e.g. a file with "ambiguity_resolution: {enabled: true}" to measure the update time with
# integer ambiguity resolution on.
# Usage: scripts/bench_live_realtime.sh [--stream FILE] [--speed S] [--ref-date YYYY/MM/DD]
#          [--lag-s L] [--rate-hz R] [--leap-s N] [--atx FILE] [--tail-s T] [--sample-s S]
#          [--config YAML] [--out DIR]
#        scripts/bench_live_realtime.sh --simulate MIN [--profile P] [--config YAML] [--out DIR]
#   --rate-hz: the recording's epoch rate (default 1), only to count the epochs before
#   the smoother's window is full (lag x rate). --leap-s: GPST - UTC of the recording
#   (default 18). --tail-s: wall seconds after the replay ends before the figures are
#   taken (default 5). --sample-s: period of the CPU lines printed during the run (default 10).
# Needs the catkin build: scripts/build.sh ppp_stream_node ppp_ekf_node ppp_smoother_node
# ppp_bench_live_stream ppp_bayes_tree_generate_messages_py. Runs its own roscore on a free
# loopback port.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
STREAM="$SHARED_DATA/streams/rtcm/week-rollover-STR24.rtcm3" SPEED=10 REF_DATE=2018/07/14 LAG_S=600 RATE_HZ=1
LEAP_S=18 ATX="$SHARED_DATA/antex/igs20_gps_satellites_trim.atx" TAIL_S=5 SIMULATE_MIN="" PROFILE=loiter NAV=""
SAMPLE_S=10
EXTRA_CONFIG=""
USER_CONFIGS=()
OUT="$(mktemp -d /tmp/bench_live_realtime.XXXXXX)"
while [ $# -gt 0 ]; do
  case "$1" in
    --stream) STREAM="$2"; shift 2 ;;
    --speed) SPEED="$2"; shift 2 ;;
    --ref-date) REF_DATE="$2"; shift 2 ;;
    --lag-s) LAG_S="$2"; shift 2 ;;
    --rate-hz) RATE_HZ="$2"; shift 2 ;;
    --leap-s) LEAP_S="$2"; shift 2 ;;
    --atx) ATX="$2"; shift 2 ;;
    --tail-s) TAIL_S="$2"; shift 2 ;;
    --sample-s) SAMPLE_S="$2"; shift 2 ;;
    --simulate) SIMULATE_MIN="$2"; shift 2 ;;
    --profile) PROFILE="$2"; shift 2 ;;
    --config) [ -r "$2" ] || { echo "bench_live_realtime.sh: cannot read --config $2" >&2; exit 2; }
              USER_CONFIGS+=("$(readlink -f "$2")"); shift 2 ;;
    --out) OUT="$2"; mkdir -p "$OUT"; shift 2 ;;
    *) echo "bench_live_realtime.sh: unknown argument $1 (see the header)" >&2; exit 2 ;;
  esac
done
for exe in ppp_stream_node ppp_ekf_node ppp_smoother_node; do
  [ -x "$BIN_DIR/$exe" ] || { echo "bench_live_realtime.sh: $exe is not built in $BIN_DIR (scripts/build.sh $exe)" >&2; exit 1; }
done
if [ -n "$SIMULATE_MIN" ]; then
  [ -x "$BIN_DIR/ppp_bench_live_stream" ] || { echo "bench_live_realtime.sh: ppp_bench_live_stream is not built" >&2; exit 1; }
  STREAM="$OUT/simulated_10hz.rtcm3" NAV="$OUT/simulated.rnx" SPEED=1 LAG_S=60 RATE_HZ=10 REF_DATE=2026/05/13
  EXTRA_CONFIG="$REPO_DIR/config/ppp_simulated.yaml"
  echo "=== simulated flight ($PROFILE, $SIMULATE_MIN min at 10 Hz) -> $STREAM"
  "$BIN_DIR/ppp_bench_live_stream" --out-rtcm "$STREAM" --out-nav "$NAV" --minutes "$SIMULATE_MIN" --rate 10 \
    --profile "$PROFILE" | tee "$OUT/ppp_bench_live_stream.log"
fi
[ -r "$STREAM" ] || { echo "bench_live_realtime.sh: cannot read the stream $STREAM" >&2; exit 1; }
[ -r "$ATX" ] || { echo "bench_live_realtime.sh: cannot read the ANTEX file $ATX" >&2; exit 1; }
PIDS=()  # started here, stopped in reverse order
cleanup() {
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do kill -INT "${PIDS[$i]}" 2>/dev/null || true; done
  for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
  stop_ros_master
}
trap cleanup EXIT
private_ros_master "$OUT"

start_ppp_node() {  # estimator namespace
  local exe="ppp_$1_node" ns="/$2" node="$2/ppp_$1_node"
  rosparam load "$REPO_DIR/config/ppp.yaml" "/$node"
  [ -n "$EXTRA_CONFIG" ] && rosparam load "$EXTRA_CONFIG" "/$node"
  rosparam load "$REPO_DIR/config/live.yaml" "/$node"
  for c in ${USER_CONFIGS[@]+"${USER_CONFIGS[@]}"}; do rosparam load "$c" "/$node"; done
  [ -n "$NAV" ] && rosparam set "/$node/ros/live/navigation_files" "[$NAV]"
  rosparam set "/$node/ros/products/atx" "[$ATX]"
  rosparam set "/$node/ros/live/observations" "[/gnss/receiver]"
  rosparam set "/$node/ros/live/reference_date" "$REF_DATE"
  rosparam set "/$node/smoother/fixed_lag_s" "$LAG_S"
  rosparam set "/$node/ros/smoothed/trajectory_csv" "$OUT/$2_smoothed_trajectory.csv"
  # Frame names per node, as launch/live.launch sets them (one TF tree, two estimates).
  rosparam set "/$node/ros/frames" "{map: $2/map, base_link: $2/base_link, odom: $2/odom, gnss_antenna: $2/gnss_antenna}"
  (cd "$OUT" && exec stdbuf -oL "$BIN_DIR/$exe" __name:="ppp_$1_node" __ns:="$ns" > "$OUT/$2.log" 2>&1) &
  PIDS+=($!)
}
start_ppp_node ekf ekf
start_ppp_node smoother smoother
/usr/bin/python3 "$REPO_DIR/scripts/live_realtime_monitor.py" --leap-s "$LEAP_S" --out "$OUT/monitor.json" \
  > "$OUT/monitor.log" 2>&1 &
MONITOR_PID=$!
PIDS+=("$MONITOR_PID")
# Ready when both nodes and the monitor are registered with the master.
for _ in $(seq 1 150); do
  n="$(rosnode list 2>/dev/null | grep -c -e /ekf/ppp_ekf_node -e /smoother/ppp_smoother_node -e /live_realtime_monitor || true)"
  [ "$n" -ge 3 ] && break
  sleep 0.2
done
sleep 1
rosparam load "$REPO_DIR/config/stream.yaml" /receiver_stream
rosparam set /receiver_stream/input "file://$STREAM?speed=$SPEED"
rosparam set /receiver_stream/output_topic /gnss/receiver
(cd "$OUT" && exec stdbuf -oL "$BIN_DIR/ppp_stream_node" __name:=receiver_stream > "$OUT/receiver_stream.log" 2>&1) &
STREAM_PID=$!
PIDS+=("$STREAM_PID")

# CPU ticks (utime + stime) of each process; the processes forked by the subshells are the exec'd ones.
HZ="$(getconf CLK_TCK)"
ticks() { awk '{print $14 + $15}' "/proc/$1/stat" 2>/dev/null || echo 0; }
names=(receiver_stream ppp_ekf_node ppp_smoother_node)
procs=("$STREAM_PID" "${PIDS[0]}" "${PIDS[1]}")
declare -a t_start
for i in 0 1 2; do t_start[$i]="$(ticks "${procs[$i]}")"; done
wall_start="$(date +%s.%N)"
echo "=== replay of ${STREAM##*/} at ${SPEED}x into ppp_ekf_node + ppp_smoother_node (live, lag ${LAG_S} s); logs in $OUT"
echo "    wall [s], CPU [% of one core] in the last ${SAMPLE_S} s: ${names[*]}"
declare -a t_last
for i in 0 1 2; do t_last[$i]="${t_start[$i]}"; done
t_sample=$SECONDS t0=$SECONDS
until grep -q "ended after" "$OUT/receiver_stream.log" 2>/dev/null; do
  kill -0 "$STREAM_PID" 2>/dev/null || { echo "ppp_stream_node stopped:"; tail -5 "$OUT/receiver_stream.log"; exit 1; }
  sleep 1
  if [ $((SECONDS - t_sample)) -ge "$SAMPLE_S" ]; then
    line="$(printf "  %6d s " $((SECONDS - t0)))"
    for i in 0 1 2; do
      now="$(ticks "${procs[$i]}")"
      line+="$(awk -v a="${t_last[$i]}" -v b="$now" -v hz="$HZ" -v s=$((SECONDS - t_sample)) \
        'BEGIN {printf "  %6.1f", 100 * (b - a) / hz / s}')"
      t_last[$i]="$now"
    done
    echo "$line"
    t_sample=$SECONDS
  fi
done
sleep "$TAIL_S"
wall_end="$(date +%s.%N)"
declare -a t_end
for i in 0 1 2; do t_end[$i]="$(ticks "${procs[$i]}")"; done
sleep 2  # one more diagnostics period
kill -INT "$MONITOR_PID" 2>/dev/null || true
wait "$MONITOR_PID" 2>/dev/null || true
[ -s "$OUT/monitor.json" ] || { echo "bench_live_realtime.sh: the monitor wrote no figures:"; tail -5 "$OUT/monitor.log"; exit 1; }
{
  echo "wall_s $(awk -v a="$wall_start" -v b="$wall_end" 'BEGIN {print b - a}')"
  for i in 0 1 2; do
    echo "cpu_s ${names[$i]} $(awk -v a="${t_start[$i]}" -v b="${t_end[$i]}" -v hz="$HZ" 'BEGIN {print (b - a) / hz}')"
  done
} > "$OUT/cpu.txt"

/usr/bin/python3 - "$OUT" "$SPEED" "$LAG_S" "$RATE_HZ" <<'EOF'
import json, math, sys
out, speed, lag_s, rate_hz = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
m = json.load(open(out + "/monitor.json"))
cpu = {}
for line in open(out + "/cpu.txt"):
    f = line.split()
    if f[0] == "wall_s": wall = float(f[1])
    else: cpu[f[1]] = float(f[2])
def q(v, p):
    if not v: return float("nan")
    v = sorted(v); return v[min(len(v) - 1, int(p * len(v)))]
def ms(v): return "%.1f / %.1f / %.1f" % (1e3 * q(v, .5), 1e3 * q(v, .99), 1e3 * max(v) if v else float("nan"))
def diag(ns):
    for name, d in m["diagnostics"].items():
        if name.endswith("ppp_%s_node: live streams" % ns): return d["values"]
    return {}
wire = m["epochs_on_wire"]
span = (m["last_frame_wall"] or 0) - (m["first_frame_wall"] or 0)
print("replay: %.0fx, %d frames, %d epochs on the wire (as the monitor saw them) in %.1f s of wall time = %.2f epochs/s; frames lost before the "
      "monitor (seq gaps): %d" % (speed, m["frames"], wire, span, wire / span if span > 0 else float("nan"),
                                  m["frame_seq_gaps"]))
print("CPU over %.1f s of wall time (/proc utime+stime; a shared, loaded machine: the per-epoch figures are the "
      "comparable ones):" % wall)
for name, s in cpu.items():
    print("  %-18s %6.2f %% of one core, %6.3f ms per epoch" % (name, 100 * s / wall, 1e3 * s / wire if wire else float("nan")))
full_window = int(lag_s * rate_hz)
published = next((int(d["values"].get("frames published", 0)) for name, d in m["diagnostics"].items()
                  if name.endswith(": stream")), 0)
for ns, label in (("ekf", "ppp_ekf_node"), ("smoother", "ppp_smoother_node")):
    n = m["nodes"]["/" + ns]
    d = diag(ns)
    def f(key):
        try: return float(d[key])
        except (KeyError, ValueError): return float("nan")
    decoded = sum(int(v.split(" / ")[0]) for k, v in d.items() if k.endswith("observation epochs decoded / ignored"))
    lost = sum(int(v) for k, v in d.items() if k.endswith("messages lost before the node (header.seq gaps)"))
    conv, dec, est = f("input CPU: message conversion [s]"), f("input CPU: decoding and release (LiveGnssInput) [s]"), f("estimator CPU [s]")
    print("%s:" % label)
    received = sum(int(v.split(" ")[0]) for k, v in d.items() if k.endswith(": messages (type)"))
    print("  epochs: on the wire %d, decoded %d, solutions out %d (solved %d); dropped (on the wire after the "
          "node's first solution, no solution out) %d%s; on the wire before it %d" %
          (wire, decoded, n["statuses"], n["solved"], n["dropped"],
           " (GPST mod 1 h [s]: %s)" % " ".join("%.1f" % k for k in n["dropped_gpst_mod_hour_s"][:5])
           if n["dropped"] else "", n["before_first_solution"]))
    print("  frames: %d published by the transport, %d received by the node, lost on the way (header.seq gaps) %d, "
          "published before its subscription connected %d" % (published, received, lost, published - received - lost))
    print("  input CPU (conversion %.3f s + decoding %.3f s) = %.3f %% of one core, %.3f ms per epoch; estimator CPU "
          "%.2f s = %.2f %% of one core, %.2f ms per epoch" % (conv, dec, 100 * (conv + dec) / wall,
                                                             1e3 * (conv + dec) / decoded if decoded else float("nan"),
                                                             est, 100 * est / wall, 1e3 * est / max(1, n["statuses"])))
    u = n["update_s"]
    print("  update time (wall) median / p99 / max [ms]: all %d epochs %s" % (len(u), ms(u)) +
          ("; after the window is full (epoch > %d): %s" % (full_window, ms(u[full_window:]))
           if ns == "smoother" and len(u) > full_window else ""))
    print("  end-to-end latency (transport read of the epoch's last frame -> status received, wall) median / p99 / "
          "max [ms]: %s (%d epochs); after the first 30 s of the replay: %s (%d epochs)" %
          (ms(n["latency_s"]), len(n["latency_s"]), ms(n["latency_steady_s"]), len(n["latency_steady_s"])))
    print("  in-node latency (callback of the epoch's last chunk -> published) median / p99 / max [ms]: %.1f / %.1f / %.1f" %
          (1e3 * f("latency median [s]"), 1e3 * f("latency p99 [s]"), 1e3 * f("latency max [s]")))
EOF
echo "=== logs and monitor.json in $OUT"

#!/usr/bin/env bash
# Node-level benchmark of live operation ("bounded memory, hours at 10 Hz"):
# a simulated flight (ppp_to_bag --simulate, GPS constellation) is replayed through
# ppp_smoother_node with config/ppp.yaml + config/ppp_simulated.yaml + an optional
# live config (default config/live.yaml: fixed lag, trajectory CSV), as fast as
# --rate says; prints the node's RSS (/proc/PID/status VmRSS) and CPU share every
# --sample-s seconds of wall time, and the rows of the smoothed-trajectory CSV.
# --sim-config YAML: the simulation's configuration (ppp_to_bag --config), e.g. with
# errors.ambiguity.satellite_phase_biases: true the bag carries the flight's phase OSBs;
# --extra-config YAML (repeatable): laid over the node's configuration last, e.g.
# "ambiguity_resolution: {enabled: true}". At the end: the node's update time
# (PppStatus.update_time_s, wall) median / p99 / max and its fixed epochs.
# Usage: scripts/bench_live_node.sh [--duration-min M] [--obs-rate 1|10] [--rate R]
#          [--profile P] [--config YAML|none] [--sim-config YAML] [--extra-config YAML]
#          [--sample-s S] [--out DIR]
# Defaults: 60 min at 1 Hz, replayed at 30x, loiter, config/live.yaml, sample 10 s.
# Needs the catkin build (scripts/build.sh ppp_smoother_node ppp_to_bag). Runs its
# own roscore on a free loopback port. Prints figures, asserts nothing.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
DURATION_MIN=60 OBS_RATE=1 RATE=30 PROFILE=loiter CONFIG="$REPO_DIR/config/live.yaml" SAMPLE_S=10
OUT="$(mktemp -d /tmp/bench_live_node.XXXXXX)"
SIM_CONFIG="" EXTRA_CONFIGS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --duration-min) DURATION_MIN="$2"; shift 2 ;;
    --obs-rate) OBS_RATE="$2"; shift 2 ;;
    --rate) RATE="$2"; shift 2 ;;
    --profile) PROFILE="$2"; shift 2 ;;
    --config) CONFIG="$2"; shift 2 ;;
    --sim-config) SIM_CONFIG="$(readlink -f "$2")"; shift 2 ;;
    --extra-config) EXTRA_CONFIGS+=("$(readlink -f "$2")"); shift 2 ;;
    --sample-s) SAMPLE_S="$2"; shift 2 ;;
    --out) OUT="$2"; mkdir -p "$OUT"; shift 2 ;;
    *) echo "bench_live_node.sh: unknown argument $1 (see the header)" >&2; exit 2 ;;
  esac
done
for exe in ppp_smoother_node ppp_to_bag; do
  [ -x "$BIN_DIR/$exe" ] || { echo "bench_live_node.sh: $exe is not built in $BIN_DIR (scripts/build.sh $exe)" >&2; exit 1; }
done
NODE_PID="" PLAY_PID="" RECORDER_PID=""
cleanup() {
  [ -n "$PLAY_PID" ] && kill -INT "$PLAY_PID" 2>/dev/null
  [ -n "$RECORDER_PID" ] && kill -TERM "$RECORDER_PID" 2>/dev/null
  [ -n "$NODE_PID" ] && kill -INT "$NODE_PID" 2>/dev/null && wait "$NODE_PID" 2>/dev/null
  stop_ros_master
}
trap cleanup EXIT
private_ros_master "$OUT"

BAG="$OUT/input.bag"
echo "=== simulated flight: $PROFILE, $DURATION_MIN min at $OBS_RATE Hz -> $BAG"
"$BIN_DIR/ppp_to_bag" --simulate "$PROFILE" --duration-min "$DURATION_MIN" --rate "$OBS_RATE" --seed 14 \
  ${SIM_CONFIG:+--config "$SIM_CONFIG"} --out "$BAG" > "$OUT/ppp_to_bag.log" 2>&1 || { tail -5 "$OUT/ppp_to_bag.log"; exit 1; }

rosparam set use_sim_time true
NS=/bench/ppp_smoother_node
rosparam load "$REPO_DIR/config/ppp.yaml" "$NS"
rosparam load "$REPO_DIR/config/ppp_simulated.yaml" "$NS"
[ "$CONFIG" != none ] && rosparam load "$CONFIG" "$NS"
for c in ${EXTRA_CONFIGS[@]+"${EXTRA_CONFIGS[@]}"}; do rosparam load "$c" "$NS"; done
rosparam set "$NS/ros/smoothed/trajectory_csv" "$OUT/smoothed_trajectory.csv"
(cd "$OUT" && exec "$BIN_DIR/ppp_smoother_node" __name:=ppp_smoother_node __ns:=/bench \
   gnss/observations:=/gnss/observations gnss/corrections:=/gnss/corrections > "$OUT/node.log" 2>&1) &
NODE_PID=$!
# The node's statuses: update time and fix state per epoch.
/usr/bin/python3 - "$OUT/statuses.txt" "$REPO_DIR/scripts" <<'PY' > "$OUT/statuses.log" 2>&1 &
import sys, rospy
sys.path.insert(0, sys.argv[2])
from live_realtime_monitor import PppStatus  # the message module alone (no geometry_msgs needed)
out = open(sys.argv[1], "w")
def on_status(m):
    out.write("%.6f %d\n" % (m.update_time_s, m.fix_state)); out.flush()
rospy.init_node("bench_status_recorder", disable_signals=True)
rospy.Subscriber("/bench/ppp/status", PppStatus, on_status, queue_size=100000)
rospy.spin()
PY
RECORDER_PID=$!
sleep 3
PID="$(pgrep -P "$NODE_PID" -x ppp_smoother_no || echo "$NODE_PID")"
echo "=== replay at ${RATE}x (node pid $PID; config ${CONFIG##*/}); wall [s], node RSS [MB], node CPU [% of one core] in the last sample"
rosbag play --clock -q -r "$RATE" "$BAG" > "$OUT/play.log" 2>&1 &
PLAY_PID=$!
HZ="$(getconf CLK_TCK)"
ticks() { awk '{print $14 + $15}' "/proc/$PID/stat"; }
t0=$SECONDS last="$(ticks)"
while kill -0 "$PLAY_PID" 2>/dev/null; do
  sleep "$SAMPLE_S"
  [ -r "/proc/$PID/status" ] || break
  now="$(ticks)"
  rss="$(awk '/VmRSS/ {printf "%.1f", $2 / 1024}' "/proc/$PID/status")"
  printf "  %6d s  RSS %7s MB  CPU %5.1f %%\n" $((SECONDS - t0)) "$rss" \
    "$(awk -v a="$last" -v b="$now" -v hz="$HZ" -v s="$SAMPLE_S" 'BEGIN {print 100 * (b - a) / hz / s}')"
  last="$now"
done
PLAY_PID=""
sleep 2
kill -INT "$NODE_PID" 2>/dev/null; wait "$NODE_PID" 2>/dev/null || true
NODE_PID=""
kill -TERM "$RECORDER_PID" 2>/dev/null; wait "$RECORDER_PID" 2>/dev/null || true  # TERM: a background job ignores INT
RECORDER_PID=""
/usr/bin/python3 - "$OUT/statuses.txt" <<'PY'
import sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
t = sorted(float(r[0]) for r in rows)
q = lambda p: 1e3 * t[min(len(t) - 1, int(p * len(t)))] if t else float("nan")
print("=== %d statuses: update time (wall) median / p99 / max %.1f / %.1f / %.1f ms; fixed epochs %d"
      % (len(t), q(.5), q(.99), 1e3 * t[-1] if t else float("nan"), sum(1 for r in rows if r[1] == "2")))
PY
if [ -f "$OUT/smoothed_trajectory.csv" ]; then
  rows=$(($(wc -l < "$OUT/smoothed_trajectory.csv") - 1))
  echo "=== smoothed trajectory: $rows rows in $OUT/smoothed_trajectory.csv (simulated epochs: $((DURATION_MIN * 60 * OBS_RATE + 1)))"
else
  echo "=== no smoothed trajectory file (full smoother: ros/smoothed/trajectory_csv is ignored)"
fi
echo "=== logs in $OUT"

#!/usr/bin/env bash
# Script test ("record and replay"): a bag recorded from the raw topics of
# a live run, replayed through launch/live.launch example:=c, gives the same output
# as the live run, epoch by epoch to 1 mm.
#  1. live run: RTKLIB's str2str as an NTRIP caster on a free loopback port, fed
#     the first 480 KiB of week-rollover-STR24.rtcm3 (paced, 40 KiB/s); live.launch example:=b with
#     receiver_spec:=ntrip://...: its ppp_stream_node pulls the caster onto
#     /gnss/receiver, ppp_ekf_node and ppp_smoother_node solve it
#     (test/rostest/live_str24.yaml: reference date, broadcast only). rosbag record
#     writes the raw topic (/gnss/receiver, rtcm_msgs/Message) to raw.bag and the
#     nodes' fixes (/ekf/ppp/fix, /smoother/ppp/fix) to live.bag.
#  2. replay: live.launch example:=c bag:=raw.bag bag_topics:=b (sim time, the same
#     nodes and configuration); rosbag record writes the fixes to replay.bag.
#  3. every fix of live.bag has a fix of replay.bag at the same stamp and the same
#     node, and the other way round; the largest 3D difference is below 1 mm.
# Runs its own roscore on a free loopback port; every step is bounded by a timeout.
# Writes one JUnit result into the directory given as $1.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin live_replay "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

skip() { junit skipped "$1"; echo "test_live_replay: skipped ($1)"; exit 0; }
for exe in ppp_ekf_node ppp_smoother_node ppp_stream_node ppp_stream_inspect; do
  [ -x "$BIN_DIR/$exe" ] || skip "$exe is not built in $BIN_DIR"
done
command -v str2str > /dev/null 2>&1 || skip "RTKLIB str2str is not installed (Debian package rtklib)"
RTCM="$SHARED_DATA/streams/rtcm/week-rollover-STR24.rtcm3"
ATX="$SHARED_DATA/antex/igs20_gps_satellites_trim.atx"
[ -f "$RTCM" ] && [ -f "$ATX" ] || skip "no shared datasets at $SHARED_DATA (set PPP_SHARED_DATA)"
FEED_BYTES=491520  # the first 480 KiB of the recording: about 7 min of data, 2,500 frames

PIDS=()  # process groups started here (setsid): stopped at exit, newest first (stop_group)
cleanup() {
  local i
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do stop_group "${PIDS[$i]}"; done
  stop_ros_master
  if [ -n "${PPP_TEST_KEEP_WORK:-}" ]; then echo "test_live_replay: logs and bags kept in $WORK"; else rm -rf "$WORK"; fi
}
trap cleanup EXIT
start() {  # log command...: in its own process group; pid in LAST
  local log="$1"; shift
  setsid "$@" > "$log" 2>&1 &
  LAST=$!
  PIDS+=("$LAST")
}
fail=""
finish() {
  if [ -z "$fail" ]; then junit passed "$1"; echo "test_live_replay: passed ($1)"
  else junit failed "$fail"; echo "test_live_replay: FAILED: $fail"; fi
  exit 0
}

private_ros_master "$WORK" || { fail="roscore did not come up on port $PORT"; finish ""; }

# wait_nodes SECONDS QUIET (started before the data flows): until both nodes' ppp/status
# went quiet for QUIET s after at least one message each (the run is processed), or
# SECONDS; prints the status counts.
wait_nodes() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys, time, rospy
limit, quiet = float(sys.argv[1]), float(sys.argv[2])
rospy.init_node("test_live_replay_wait", anonymous=True, disable_signals=True)
count, last = {}, [time.time()]
def seen(name):
    def cb(_):
        count[name] = count.get(name, 0) + 1
        last[0] = time.time()
    return cb
subs = [rospy.Subscriber(f"/{n}/ppp/status", rospy.AnyMsg, seen(n), queue_size=5000) for n in ("ekf", "smoother")]
start = time.time()
while time.time() - start < limit:
    if len(count) == 2 and time.time() - last[0] > quiet:
        break
    time.sleep(0.2)
print(" ".join(f"{n}={count.get(n, 0)}" for n in ("ekf", "smoother")))
PY
}
# subscribers TOPIC: how many nodes subscribe TOPIC (master).
subscribers() {
  /usr/bin/python3 -c '
import sys, rosgraph
state = rosgraph.Master("/test_live_replay").getSystemState()
print(sum(len(nodes) for topic, nodes in state[1] if topic == sys.argv[1]))' "$1"
}

# ---------------------------------------------------------------- 1. live run
CASTER_PORT="$(free_port)"
mkfifo "$WORK/feed"
exec 3<> "$WORK/feed"   # held open (read-write: no block) until the whole file is written
# (not through start: a background command's stdin would be /dev/null)
setsid str2str -out "ntripc://rover:secret@:$CASTER_PORT/STR24" < "$WORK/feed" > "$WORK/str2str.log" 2>&1 &
STR2STR_PID=$!
PIDS+=("$STR2STR_PID")
start "$WORK/live_launch.log" roslaunch "$REPO_DIR/launch/live.launch" example:=b atx:="$ATX" \
  receiver_spec:="ntrip://rover:secret@127.0.0.1:$CASTER_PORT/STR24?version=2&format=rtcm3&reconnect_min_s=0.2&reconnect_max_s=1&stall_timeout_s=60" \
  extra_config:="$REPO_DIR/test/rostest/live_str24.yaml"
LIVE_LAUNCH=$LAST
start "$WORK/record_raw.log" rosbag record -O "$WORK/raw.bag" /gnss/receiver
RECORD_RAW=$LAST
start "$WORK/record_live.log" rosbag record -O "$WORK/live.bag" /ekf/ppp/fix /smoother/ppp/fix
RECORD_LIVE=$LAST
wait_nodes 120 4 > "$WORK/live_counts" 2> "$WORK/wait_live.log" &
WAIT_LIVE=$!
# Both nodes and the recorder subscribe /gnss/receiver.
n=0
for _ in $(seq 1 150); do
  n="$(subscribers /gnss/receiver 2>/dev/null || echo 0)"
  [ "$n" -ge 3 ] && break
  sleep 0.2
done
[ "$n" -ge 3 ] || { fail="only $n subscribers of /gnss/receiver after 30 s (see live_launch.log)"; tail -20 "$WORK/live_launch.log"; finish ""; }
sleep 3  # the NTRIP connection and the TCPROS connections settle
timeout 60 /usr/bin/python3 - "$RTCM" "$FEED_BYTES" >&3 <<'PY'
import sys, time
data = open(sys.argv[1], "rb").read()[:int(sys.argv[2])]
# 40 KiB/s (about 35x real time): str2str passes its input on as it comes, and rosbag
# record's subscriber queue (100 messages, fixed) must absorb the bursts on a loaded machine.
for i in range(0, len(data), 2048):
    sys.stdout.buffer.write(data[i:i + 2048]); sys.stdout.buffer.flush(); time.sleep(0.05)
PY
[ $? -eq 0 ] || fail+="feeding the caster failed or took over 60 s (see str2str.log); "
exec 3>&-
wait "$WAIT_LIVE"
live_counts="$(cat "$WORK/live_counts")"
echo "live run: statuses $live_counts"
stop_group "$RECORD_RAW"; stop_group "$RECORD_LIVE"; stop_group "$LIVE_LAUNCH"; stop_group "$STR2STR_PID"
[ -f "$WORK/raw.bag" ] && [ -f "$WORK/live.bag" ] || { fail="the live run wrote no raw.bag / live.bag"; finish ""; }

# ---------------------------------------------------------------- 2. replay
start "$WORK/replay_launch.log" roslaunch "$REPO_DIR/launch/live.launch" example:=c bag:="$WORK/raw.bag" bag_topics:=b \
  start_delay:=10 atx:="$ATX" extra_config:="$REPO_DIR/test/rostest/live_str24.yaml"
REPLAY_LAUNCH=$LAST
start "$WORK/record_replay.log" rosbag record -O "$WORK/replay.bag" /ekf/ppp/fix /smoother/ppp/fix
RECORD_REPLAY=$LAST
wait_nodes 150 4 > "$WORK/replay_counts" 2> "$WORK/wait_replay.log" &
WAIT_REPLAY=$!
for _ in $(seq 1 600); do
  grep -qE '\[player-[0-9]+\] process has finished cleanly' "$WORK/replay_launch.log" && break
  sleep 0.2
done
grep -qE '\[player-[0-9]+\] process has finished cleanly' "$WORK/replay_launch.log" \
  || fail+="the player did not finish within 120 s; "
wait "$WAIT_REPLAY"
replay_counts="$(cat "$WORK/replay_counts")"
echo "replay: statuses $replay_counts"
stop_group "$RECORD_REPLAY"; stop_group "$REPLAY_LAUNCH"
[ -f "$WORK/replay.bag" ] || { fail+="the replay wrote no replay.bag"; finish ""; }

# ---------------------------------------------------------------- 3. compare
# The RTCM 3 frames with a good CRC-24Q in the bytes fed (ppp_stream_inspect --json "frames").
head -c "$FEED_BYTES" "$RTCM" > "$WORK/fed.rtcm3"
frames="$("$BIN_DIR/ppp_stream_inspect" "$WORK/fed.rtcm3" --json 2> "$WORK/inspect.err" \
  | /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin)["frames"])')"
[[ "$frames" =~ ^[0-9]+$ ]] || { fail+="ppp_stream_inspect gave no frame count for the bytes fed ($(head -c 300 "$WORK/inspect.err")); "; finish ""; }
result="$(/usr/bin/python3 - "$WORK/raw.bag" "$WORK/live.bag" "$WORK/replay.bag" "$frames" <<'PY'
import math, sys, rosbag
def ecef(m):
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    lat, lon, h = math.radians(m.latitude), math.radians(m.longitude), m.altitude
    n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
    return ((n + h) * math.cos(lat) * math.cos(lon), (n + h) * math.cos(lat) * math.sin(lon), (n * (1 - e2) + h) * math.sin(lat))
def fixes(path):
    out = {}
    with rosbag.Bag(path) as b:
        for topic, m, _ in b.read_messages(topics=["/ekf/ppp/fix", "/smoother/ppp/fix"]):
            out.setdefault(topic, {})[m.header.stamp.to_nsec()] = ecef(m)
    return out
with rosbag.Bag(sys.argv[1]) as raw:
    info = raw.get_type_and_topic_info().topics.get("/gnss/receiver")
    raw_msgs = info.message_count if info else 0
    raw_type = info.msg_type if info else "none"
live, replay = fixes(sys.argv[2]), fixes(sys.argv[3])
frames = int(sys.argv[4])
problems, figures = [], [f"raw.bag: {raw_msgs} {raw_type} messages ({frames} frames fed)"]
if raw_type != "rtcm_msgs/Message": problems.append(f"/gnss/receiver recorded as {raw_type}")
if raw_msgs != frames:  # rosbag record drops when its 100-message subscriber queue overflows
    problems.append(f"raw.bag holds {raw_msgs} of the {frames} frames (the recorder or the stream dropped some)")
for topic in ("/ekf/ppp/fix", "/smoother/ppp/fix"):
    a, b = live.get(topic, {}), replay.get(topic, {})
    if len(a) < 400: problems.append(f"{topic}: only {len(a)} live fixes")
    only_live, only_replay = sorted(set(a) - set(b)), sorted(set(b) - set(a))
    if only_live or only_replay:
        problems.append(f"{topic}: {len(only_live)} stamps only live, {len(only_replay)} only replayed")
    common = set(a) & set(b)
    worst = max((math.dist(a[k], b[k]) for k in common), default=float("nan"))
    if not worst < 1e-3: problems.append(f"{topic}: largest difference {worst * 1e3:.3g} mm")
    figures.append(f"{topic}: {len(a)} live, {len(b)} replayed, {len(common)} compared, largest difference {worst * 1e3:.3g} mm")
print("; ".join(figures))
print("; ".join(problems))
PY
)"
figures="$(echo "$result" | sed -n 1p)"
problems="$(echo "$result" | sed -n 2p)"
echo "test_live_replay: $figures"
[ -n "$figures" ] || fail+="the comparison failed to run; "
[ -z "$problems" ] || fail+="$problems; "
if [ -n "$fail" ]; then
  echo "--- live_launch.log (tail)"; tail -15 "$WORK/live_launch.log"
  echo "--- replay_launch.log (tail)"; tail -15 "$WORK/replay_launch.log"
fi
finish "live statuses $live_counts, replayed $replay_counts; $figures"

#!/usr/bin/env bash
# Script test ("start-up errors that print nothing"): both PPP nodes (and
# ppp_stream_node, which shares their start-up: ros/node_main.h runNode),
# started with a bad parameter or a missing product file, exit with code 1 and
# say on stderr what is wrong (the key path or the file, and the reason); a node
# started before the master says at once which master it waits for.
# Runs its own roscore on a free loopback port; every node run is bounded by a
# timeout. Writes one JUnit result into the directory given as $1.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin node_startup "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

for exe in ppp_ekf_node ppp_smoother_node ppp_stream_node; do
  if [ ! -x "$BIN_DIR/$exe" ]; then junit skipped "$exe is not built in $BIN_DIR"; echo "test_node_startup: skipped"; exit 0; fi
done
trap 'stop_ros_master; rm -rf "$WORK"' EXIT
if ! private_ros_master "$WORK"; then
  junit failed "roscore did not come up on port $PORT"; echo "test_node_startup: FAILED: no roscore"; exit 0
fi

ATX="$SHARED_DATA/antex/igs20_zim2_gps_trim.atx"
fail=""
cases=0
# expect NODE "PARAM:=VALUE ..." "text stderr must hold" ...
expect() {
  local node="$1" args="$2"; shift 2
  cases=$((cases + 1))
  local err="$WORK/case$cases.err"
  # shellcheck disable=SC2086
  timeout 60 "$BIN_DIR/$node" __name:="startup_case$cases" $args > /dev/null 2> "$err"
  local rc=$?
  [ $rc -eq 1 ] || fail+="case $cases ($node $args): exit $rc, expected 1; "
  for want in "$@"; do
    grep -qF -- "$want" "$err" || fail+="case $cases ($node $args): stderr lacks '$want' (got: $(head -c 300 "$err" | tr '\n' ' ')); "
  done
}
expect ppp_ekf_node "_stochastic/position/inital_sigma_m:=1.0" "ppp_ekf_node: cannot start" "inital_sigma_m" "unknown key"
expect ppp_smoother_node "_stochastic/position/inital_sigma_m:=1.0" "ppp_smoother_node: cannot start" "inital_sigma_m" "unknown key"
expect ppp_ekf_node "_estimator/min_satellites:=-3" "min_satellites"
expect ppp_ekf_node "_measurement_model/troposphere/mapping:=hopfeld" "mapping" "hopfeld"
expect ppp_ekf_node "_stochastic/zwd/initial_sigma_m:=nan" "initial_sigma_m"
# A list parameter comes from the parameter server (a command-line _param:= is a scalar).
atx_list() { rosparam set "/startup_case$((cases + 1))/ros/products/atx" "[$1]"; }
atx_list "$WORK/missing.atx"
expect ppp_ekf_node "" "$WORK/missing.atx" "cannot open"
atx_list "$ATX"
expect ppp_ekf_node "_ros/products/bias:=$WORK/missing.bia" "$WORK/missing.bia" "cannot open"
atx_list "$ATX"
expect ppp_ekf_node "_ros/products/blq:=$WORK/missing.blq" "$WORK/missing.blq" "cannot open"
# A list given as a single text is refused with the key path.
expect ppp_ekf_node "_ros/products/atx:=$ATX" "ros.products.atx" "expected a list"

# A key written twice in a configuration file: the parameter server keeps only the last,
# so the node reads the files named by config_files again and refuses the file (path, line).
DUP="$WORK/dup key.yaml"
printf 'estimator:\n  min_satellites: 5\nestimator:\n  min_satellites: 9\n' > "$DUP"
rosparam set "/startup_case$((cases + 1))/config_files" "['$DUP']"
expect ppp_ekf_node "" "$DUP" "estimator" "line 1 and line 3"
rosparam set "/startup_case$((cases + 1))/config_files" "$DUP"
expect ppp_smoother_node "" "config_files" "expected a list"
# The same through the launch file a user starts: config:= names the file.
cases=$((cases + 1))
timeout 60 roslaunch --wait ppp_bayes_tree ppp_ekf.launch ns:=launchdup "config:=$DUP" > "$WORK/launchdup.log" 2>&1 &
launch_pid=$!
for i in $(seq 1 300); do
  grep -q "line 1 and line 3" "$WORK/launchdup.log" && break
  kill -0 "$launch_pid" 2> /dev/null || break
  sleep 0.1
done
kill -INT "$launch_pid" 2> /dev/null; wait "$launch_pid" 2> /dev/null
grep -qF "$DUP" "$WORK/launchdup.log" && grep -q "line 1 and line 3" "$WORK/launchdup.log" \
  || fail+="launch with a key written twice: the node did not refuse the file (got: $(grep -i 'cannot start\|error' "$WORK/launchdup.log" | head -c 300 | tr '\n' ' ')); "

# ppp_stream_node shares the start-up (ros/node_main.h runNode).
expect ppp_stream_node "" "ppp_stream_node: cannot start" "parameter ~input" "is required"
expect ppp_stream_node "_input:=serial:///dev/ttyACM0?baud=12345" "ppp_stream_node: cannot start" "baud=12345"

# Before the master: a port with nothing listening.
DEAD_PORT="$(free_port)"
timeout 5 env ROS_MASTER_URI="http://127.0.0.1:$DEAD_PORT" "$BIN_DIR/ppp_ekf_node" > /dev/null 2> "$WORK/nomaster.err"
grep -qF "waiting for the ROS master at http://127.0.0.1:$DEAD_PORT" "$WORK/nomaster.err" \
  || fail+="no master: stderr lacks the waiting message (got: $(head -c 300 "$WORK/nomaster.err" | tr '\n' ' ')); "
cases=$((cases + 1))

if [ -z "$fail" ]; then
  junit passed ""
  echo "test_node_startup: passed ($cases cases)"
else
  junit failed "$fail"
  echo "test_node_startup: FAILED: $fail"
fi

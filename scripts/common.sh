# Sourced by the scripts: paths and environment shared by all of them.
# The machine's default python3 may be a pyenv build without the ROS modules:
# catkin must see Debian's python3 first.
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
REPO_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
WS_DIR="${PPP_WS_DIR:-$REPO_DIR/build_ws}"
BIN_DIR="$WS_DIR/devel/lib/ppp_bayes_tree"
JOBS="${PPP_JOBS:-$(nproc 2>/dev/null || echo 2)}"
SHARED_DATA="${PPP_SHARED_DATA:-$(cd "$REPO_DIR/.." && pwd -P)/shared/data}"

# write_junit FILE SUITE NAME STATUS MESSAGE: one JUnit test case (STATUS passed,
# failed or skipped) for scripts/summarize_tests.py; the message is made XML-safe.
write_junit() {
  local file="$1" suite="$2" name="$3" status="$4" msg="${5//\"/\'}"
  msg="${msg//&/and}"; msg="${msg//</(}"; msg="${msg//>/)}"
  {
    echo '<?xml version="1.0" encoding="UTF-8"?>'
    echo "<testsuite name=\"$suite\" tests=\"1\">"
    echo "  <testcase classname=\"$suite\" name=\"$name\">"
    case "$status" in
      failed) echo "    <failure message=\"$msg\"/>" ;;
      skipped) echo "    <skipped message=\"$msg\"/>" ;;
    esac
    echo "  </testcase>"
    echo "</testsuite>"
  } > "$file"
}

# script_test_begin NAME RESULT_DIR: the set-up of a script test (scripts/test_NAME.sh):
# OUT = RESULT_DIR (created), WORK = a fresh temporary directory removed at exit, and
# junit STATUS MESSAGE writing its one JUnit result OUT/script-NAME.xml.
script_test_begin() {
  SCRIPT_TEST_NAME="$1"
  OUT="${2:?usage: test_$1.sh RESULT_DIR}"
  mkdir -p "$OUT"
  WORK="$(mktemp -d "/tmp/ppp_test_$1.XXXXXX")"
  trap 'rm -rf "$WORK"' EXIT
  junit() { write_junit "$OUT/script-$SCRIPT_TEST_NAME.xml" script_tests "$SCRIPT_TEST_NAME" "$1" "$2"; }  # status message
}

# free_port: a free TCP port on the loopback interface (the kernel picks it).
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

# stop_group PID: SIGINT to the process group PID leads (a command started with setsid),
# SIGKILL to the group when PID still runs after 10 s.
stop_group() {
  local pid="$1" k
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -INT -- "-$pid" 2>/dev/null || true
  for k in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.2; done
  kill -KILL -- "-$pid" 2>/dev/null || true
}

# private_ros_master DIR: a run with its own ROS master on a free loopback port: sources
# the workspace's devel/setup.bash, sets ROS_HOME and ROS_LOG_DIR under DIR, ROS_IP, PORT
# and ROS_MASTER_URI, starts roscore (its own process group, pid ROSCORE_PID, log
# DIR/roscore.log) and waits until it answers (20 s at most). Returns 1 with a message on
# stderr when it did not come up. The caller stops it with stop_ros_master (in its EXIT
# trap, set before this call, after the nodes it started).
private_ros_master() {
  set +u  # ROS's setup scripts read unset variables
  # shellcheck disable=SC1091
  source "$WS_DIR/devel/setup.bash"
  set -u
  export ROS_HOME="$1/ros_home" ROS_LOG_DIR="$1/ros_log" ROS_IP=127.0.0.1
  PORT="$(free_port)"
  export ROS_MASTER_URI="http://127.0.0.1:$PORT"
  setsid roscore -p "$PORT" > "$1/roscore.log" 2>&1 &
  ROSCORE_PID=$!
  local i
  for i in $(seq 1 100); do
    rosparam get /rosdistro > /dev/null 2>&1 && return 0
    kill -0 "$ROSCORE_PID" 2>/dev/null || break
    sleep 0.2
  done
  echo "roscore did not come up on port $PORT (see $1/roscore.log)" >&2
  return 1
}

# stop_ros_master: stops the roscore of private_ros_master (stop_group), if it runs.
stop_ros_master() {
  [ -n "${ROSCORE_PID:-}" ] || return 0
  stop_group "$ROSCORE_PID"
  wait "$ROSCORE_PID" 2>/dev/null || true
  ROSCORE_PID=""
}

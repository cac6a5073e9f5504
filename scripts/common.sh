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

# private_ros_master DIR: the environment of a run with its own ROS master on a free
# loopback port: sources the workspace's devel/setup.bash, sets ROS_HOME and ROS_LOG_DIR
# under DIR, ROS_IP, PORT and ROS_MASTER_URI. The caller starts `roscore -p "$PORT"`.
private_ros_master() {
  set +u  # ROS's setup scripts read unset variables
  # shellcheck disable=SC1091
  source "$WS_DIR/devel/setup.bash"
  set -u
  export ROS_HOME="$1/ros_home" ROS_LOG_DIR="$1/ros_log" ROS_IP=127.0.0.1
  PORT="$(free_port)"
  export ROS_MASTER_URI="http://127.0.0.1:$PORT"
}

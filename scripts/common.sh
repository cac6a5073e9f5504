# Sourced by the scripts: paths and environment shared by all of them.
# The machine's default python3 may be a pyenv build without the ROS modules:
# catkin must see Debian's python3 first.
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
REPO_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
WS_DIR="${PPP_WS_DIR:-$REPO_DIR/build_ws}"
BIN_DIR="$WS_DIR/devel/lib/ppp_bayes_tree"
JOBS="${PPP_JOBS:-$(nproc 2>/dev/null || echo 2)}"
SHARED_DATA="${PPP_SHARED_DATA:-$(cd "$REPO_DIR/.." && pwd -P)/shared/data}"

#!/usr/bin/env bash
# Builds the catkin workspace build_ws/ (git-ignored) whose src/ links to this
# repository. Release by default; extra arguments go to catkin_make.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

mkdir -p "$WS_DIR/src"
link="$WS_DIR/src/ppp_bayes_tree"
if [ ! -L "$link" ] || [ "$(readlink -f "$link")" != "$REPO_DIR" ]; then
  rm -rf "$link"
  ln -s "$REPO_DIR" "$link"
fi
# A workspace needs its top-level CMakeLists.txt (catkin's toplevel.cmake).
if [ ! -e "$WS_DIR/src/CMakeLists.txt" ]; then
  ln -s /usr/share/catkin/cmake/toplevel.cmake "$WS_DIR/src/CMakeLists.txt"
fi

cd "$WS_DIR"
catkin_make -DCMAKE_BUILD_TYPE="${PPP_BUILD_TYPE:-Release}" -j"$JOBS" "$@"

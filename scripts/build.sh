#!/usr/bin/env bash
# Builds the catkin workspace build_ws/ (git-ignored) whose src/ links to this
# repository. Release by default; extra arguments go to catkin_make.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

# build_ws/src/ppp_bayes_tree is a real directory of symlinks to the repository's
# top-level entries, all but the build directories. It must not be a symlink to
# the repository itself: the repository holds build_ws, so tools that walk a
# package with followlinks (roslaunch/rosrun resolving `pkg file.launch` or a node
# type: roslib.packages.find_resource) would loop through build_ws/src/ppp_bayes_tree
# 40 levels deep (until ELOOP), walking the whole build tree each time, and then
# refuse the launch file as "multiple files named ... in package".
mkdir -p "$WS_DIR/src"
pkg="$WS_DIR/src/ppp_bayes_tree"
[ -L "$pkg" ] && rm -f "$pkg"  # the old layout: one symlink to the repository
mkdir -p "$pkg"
for entry in "$REPO_DIR"/* "$REPO_DIR"/.[!.]*; do
  [ -e "$entry" ] || continue
  name="$(basename "$entry")"
  case "$name" in .git|build|build_*|build-*) continue ;; esac
  [ "$(readlink -f "$entry")" = "$(readlink -f "$WS_DIR")" ] && continue
  if [ "$(readlink "$pkg/$name" 2>/dev/null)" != "$entry" ]; then
    rm -rf "$pkg/$name"
    ln -s "$entry" "$pkg/$name"
  fi
done
for link in "$pkg"/* "$pkg"/.[!.]*; do  # entries removed from the repository
  if [ -L "$link" ] && [ ! -e "$link" ]; then rm -f "$link"; fi
done
# A workspace needs its top-level CMakeLists.txt (catkin's toplevel.cmake).
if [ ! -e "$WS_DIR/src/CMakeLists.txt" ]; then
  ln -s /usr/share/catkin/cmake/toplevel.cmake "$WS_DIR/src/CMakeLists.txt"
fi

cd "$WS_DIR"
catkin_make -DCMAKE_BUILD_TYPE="${PPP_BUILD_TYPE:-Release}" -j"$JOBS" "$@"

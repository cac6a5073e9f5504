#!/usr/bin/env bash
# Installs the Debian (bookworm) packages the project needs that are missing.
# Does nothing, quickly, when all of them are present.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

PACKAGES=(
  # build and ROS 1
  catkin libroscpp-dev librosbag-dev libtf2-ros-dev libtf2-eigen-dev libnav-msgs-dev
  libsensor-msgs-dev libgeometry-msgs-dev ros-message-generation libdiagnostic-updater-dev
  ros-std-msgs ros-geometry-msgs python3-rosbag
  python3-roslaunch python3-rosmaster python3-rostest librostest-dev rosbash rviz
  # numerics, geodesy, compression, configuration files
  libeigen3-dev libsuitesparse-dev libgeographiclib-dev zlib1g-dev libyaml-cpp-dev
  # the allocator of the batch tools (Monte Carlo, campaigns; CMakeLists.txt)
  libtcmalloc-minimal4
  # tests, benchmarks, fuzzing (clang's libFuzzer), plots, the peer we measure against
  libgtest-dev libbenchmark-dev clang libclang-rt-14-dev python3-matplotlib rtklib
  # the serial-port tests (a pseudo-terminal pair), the RViz screenshot (a virtual display)
  socat xvfb x11-apps
  # campaigns on a cluster: the single-node Slurm of scripts/test_campaign_slurm.sh
  slurm-wlm munge
)

missing=()
for p in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null || true)
  [[ "$status" == ii* ]] || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "setup_deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup_deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# Real-time benchmark of the GNSS/INS path (no ROS): builds ppp_bench_ins_realtime
# (src/bench) and runs it at the lowest priority (nice -n 19). A simulated flight
# (GPS + Galileo, PPP-AR on, industrial MEMS IMU; default 200 Hz IMU, 10 Hz GNSS,
# 5 min, seed 7) is fed in time order to ekf_ins with the odometry at the IMU rate
# (the PPP node's per-reading work) and to smoother_ins with the smoother section of
# config/live.yaml (the live runs' fixed lag 60 s, wildfire threshold 1 mm; another
# --smoother-config or --lag-s given here overrides it). Prints p50 / p90 / p99 / max and counts of the odometry
# latency per IMU reading and of the GNSS epoch step of both estimators, the
# smoother's update by step, the fixed share, and whether the targets (odometry p99
# < 2 ms, smoother_ins epoch step p99 < 10 ms) are met. Also prints the machine's
# load before and after: on a shared machine the wall-clock figures are pessimistic
# (the thread CPU line of the smoother shows its own cost). Asserts nothing.
# Usage: scripts/bench_ins_realtime.sh [--no-build] [ppp_bench_ins_realtime options]
#   e.g. --minutes 5 --seed 7 --lag-s 60 --gnss-rate-hz 10 --imu-rate-hz 200 --smoother-config YAML
#        --profile loiter|survey|figure8|climb --csv FILE (per smoother epoch) --ekf-only
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD=1
if [ "${1:-}" = "--no-build" ]; then BUILD=0; shift; fi
if [ "$BUILD" = 1 ]; then
  [ -d "$WS_DIR/build" ] || { echo "bench_ins_realtime.sh: no build in $WS_DIR: run scripts/build.sh first" >&2; exit 2; }
  nice -n 19 make -C "$WS_DIR/build" -j2 ppp_bench_ins_realtime >/dev/null
fi
EXE="$BIN_DIR/ppp_bench_ins_realtime"
[ -x "$EXE" ] || { echo "bench_ins_realtime.sh: $EXE not built" >&2; exit 2; }
echo "commit $(git -C "$REPO_DIR" rev-parse --short HEAD)$(git -C "$REPO_DIR" diff --quiet HEAD -- src include || echo ' (modified)'); $(nproc) cores; $(uptime)"
nice -n 19 "$EXE" --smoother-config "$REPO_DIR/config/live.yaml" "$@"

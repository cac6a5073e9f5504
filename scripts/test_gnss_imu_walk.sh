#!/usr/bin/env bash
# Script test of scripts/peers/gnss_imu_walk.py: runs its unit test
# (test/scripts/test_gnss_imu_walk.py: a missing peer checkout is refused with the clone
# command; the peer's input and output files on series known by construction; no peer
# needed) and, when GNSS_IMU_PEER_DIR names a checkout of the peer and the shared data and
# a built ppp_solve are there, the comparison itself, which must print its table.
# Writes one JUnit result into the directory given as $1 (scripts/test.sh's extra dir).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin gnss_imu_walk "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

LOG="$WORK/peer.log"
fail=""
/usr/bin/python3 "$REPO_DIR/test/scripts/test_gnss_imu_walk.py" > "$LOG" 2>&1 || fail+="unit test failed: $(tail -1 "$LOG"); "
DATA="${PPP_SHARED_DATA:-$REPO_DIR/../shared/data}"
BIN="$REPO_DIR/build_ws/devel/lib/ppp_bayes_tree"
if [[ -n "${GNSS_IMU_PEER_DIR:-}" && -f "$DATA/streams/ubx/imu_1730.csv" && -x "$BIN/ppp_solve" ]]; then
  /usr/bin/python3 "$REPO_DIR/scripts/peers/gnss_imu_walk.py" --peer-dir "$GNSS_IMU_PEER_DIR" --bin "$BIN" \
    --data "$DATA" --out "$WORK/run" >> "$LOG" 2>&1 || fail+="the comparison exited non-zero; "
  grep -q '^| horizontal velocity RMS \[m/s\], from its first GNSS epoch | [0-9.]* | [0-9.]* | [0-9.]* |' "$LOG" ||
    fail+="no velocity row in the table; "
fi
if [[ -n "$fail" ]]; then
  junit failed "$fail"
  echo "test_gnss_imu_walk: FAILED: $fail"; cat "$LOG"
else
  junit passed ""
  echo "test_gnss_imu_walk: ok"
fi

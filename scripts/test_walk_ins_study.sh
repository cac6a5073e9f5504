#!/usr/bin/env bash
# Script test of scripts/walk_ins_study.py: runs its unit test
# (test/scripts/test_walk_ins_study.py, series whose velocities, courses and
# displacements are known by construction) and, when the shared data and a built
# ppp_solve are there, the study itself, which must print its table.
# Writes one JUnit result into the directory given as $1 (scripts/test.sh's extra dir).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin walk_ins_study "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

LOG="$WORK/study.log"
fail=""
/usr/bin/python3 "$REPO_DIR/test/scripts/test_walk_ins_study.py" > "$LOG" 2>&1 || fail+="unit test failed: $(tail -1 "$LOG"); "
DATA="${PPP_SHARED_DATA:-$REPO_DIR/../shared/data}"
BIN="$REPO_DIR/build_ws/devel/lib/ppp_bayes_tree"
if [[ -f "$DATA/streams/ubx/imu_1730.csv" && -x "$BIN/ppp_solve" ]]; then
  /usr/bin/python3 "$REPO_DIR/scripts/walk_ins_study.py" --bin "$BIN" --data "$DATA" --out "$WORK/run" >> "$LOG" 2>&1 ||
    fail+="the study exited non-zero; "
  grep -q '^| horizontal velocity RMS \[m/s\] | [0-9.]* | [0-9.]* |$' "$LOG" || fail+="no velocity row in the table; "
fi
if [[ -n "$fail" ]]; then
  junit failed "$fail"
  echo "test_walk_ins_study: FAILED: $fail"; cat "$LOG"
else
  junit passed ""
  echo "test_walk_ins_study: ok"
fi

#!/usr/bin/env bash
# Script test of scripts/rtklib_restart_study.py: ZIM2 from 00:00 through both programs.
# RTKLIB's row must give the peer figures of ../shared/data/README.md ("Peer results",
# RTKLIB forward EKF on ZIM2: mean 17.7 cm, below 10 cm from 29.5 min), which checks
# that the script feeds rnx2rtkp as the peers were run; ours must give a row too; a
# start outside the hour must be refused. Skipped without rnx2rtkp, the shared data or
# a built ppp_solve. Writes one JUnit result into the directory given as $1.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin rtklib_restart_study "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

DATA="${PPP_SHARED_DATA:-$REPO_DIR/../shared/data}"
BIN="$REPO_DIR/build_ws/devel/lib/ppp_bayes_tree"
if ! command -v rnx2rtkp > /dev/null || [[ ! -d "$DATA/zim2-2026-133" || ! -x "$BIN/ppp_solve" ]]; then
  junit skipped "needs rnx2rtkp (Debian rtklib), the shared ZIM2 hour and a built ppp_solve"
  echo "test_rtklib_restart_study: skipped"; exit 0
fi
LOG="$WORK/study.log"
fail=""
PPP_SHARED_DATA="$DATA" /usr/bin/python3 "$REPO_DIR/scripts/rtklib_restart_study.py" "$BIN" "$WORK/run" \
  --starts 0 zim2 > "$LOG" 2>&1 || fail+="the study exited non-zero; "
# | 00:00 | 59.5 | OURS / 29.5 | OURS_MEAN / 17.7 | ...
grep -qE '^\| 00:00 \| 59\.5 \| ([0-9.]+|never) / 29\.5 \| [0-9.]+ / 17\.7 \|' "$LOG" ||
  fail+="RTKLIB's row differs from the peer figures (29.5 min, 17.7 cm); "
/usr/bin/python3 "$REPO_DIR/scripts/rtklib_restart_study.py" "$BIN" "$WORK/bad" --starts 50 zim2 > "$WORK/bad.log" 2>&1 &&
  fail+="a start after the hour was not refused; "
grep -q 'each start in 0..45 min' "$WORK/bad.log" || fail+="no reason for the refused start; "
if [[ -n "$fail" ]]; then
  junit failed "$fail"
  echo "test_rtklib_restart_study: FAILED: $fail"; cat "$LOG"
else
  junit passed ""
  echo "test_rtklib_restart_study: ok"
fi

#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the gtest units through
# catkin (and rostests as they come), then a short libFuzzer smoke run of every
# reader, then the script tests (scripts/test_plot_solutions.sh;
# scripts/test_nl_residual_histogram.sh; scripts/test_function_census.sh: the
# function-length census and its unit test; scripts/test_walk_ins_study.sh: the
# u-blox walk GNSS/INS study and its unit test; scripts/test_gnss_imu_walk.sh: the
# walk's own GNSS/IMU filter beside ours (its unit test; the run when GNSS_IMU_PEER_DIR
# names a checkout of the peer); scripts/test_rtklib_restart_study.sh: float
# restarts beside RTKLIB, whose row must give the shared data's peer figures;
# scripts/test_demo.sh: the main-job
# demo end to end on a 3-min simulated flight;
# scripts/test_node_startup.sh: start-up errors of the nodes reach stderr;
# scripts/test_live_replay.sh: a bag of a live run's raw topics replayed through
# launch/live.launch gives the live run's output; scripts/test_campaign_slurm.sh:
# ppp_campaign on a private single-node Slurm cluster against the local pool).
# Closes with "N passed, N failed, N skipped"; exits non-zero on any failure.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

"$REPO_DIR/scripts/setup_deps.sh" || { echo "test.sh: dependency setup failed"; echo "0 passed, 1 failed"; exit 1; }
"$REPO_DIR/scripts/build.sh" || { echo "test.sh: build failed"; echo "0 passed, 1 failed"; exit 1; }

RESULTS="$WS_DIR/build/test_results"
EXTRA="$WS_DIR/extra_test_results"
rm -rf "$RESULTS" "$EXTRA"
mkdir -p "$EXTRA"

export PPP_SHARED_DATA="$SHARED_DATA"
if [ -d "$SHARED_DATA" ]; then
  echo "test.sh: shared datasets at $SHARED_DATA"

else
  echo "test.sh: no shared datasets at $SHARED_DATA: tests that need them are skipped"
fi

echo "=== unit tests (catkin run_tests) ==="
(cd "$WS_DIR" && catkin_make run_tests -j"$JOBS") > "$WS_DIR/run_tests.log" 2>&1
rc=$?
grep -E '^\[ *(OK|FAILED|SKIPPED) *\]|error:|Failure|Expected|Which is|evaluates to|Skipped' "$WS_DIR/run_tests.log"
if [ $rc -ne 0 ]; then
  echo "test.sh: 'catkin_make run_tests' failed (exit $rc); see $WS_DIR/run_tests.log"
  tail -20 "$WS_DIR/run_tests.log"
  printf '<testsuite><testcase classname="catkin" name="run_tests"><failure message="catkin_make run_tests exited %s"/></testcase></testsuite>\n' "$rc" > "$EXTRA/catkin-run_tests.xml"
fi

echo "=== fuzz smoke (libFuzzer over seed corpora and malformed fixtures) ==="
"$REPO_DIR/scripts/fuzz_smoke.sh" "$EXTRA"

echo "=== script tests ==="
"$REPO_DIR/scripts/test_plot_solutions.sh" "$EXTRA"
"$REPO_DIR/scripts/test_nl_residual_histogram.sh" "$EXTRA"
"$REPO_DIR/scripts/test_function_census.sh" "$EXTRA"
"$REPO_DIR/scripts/test_walk_ins_study.sh" "$EXTRA"
"$REPO_DIR/scripts/test_gnss_imu_walk.sh" "$EXTRA"
"$REPO_DIR/scripts/test_rtklib_restart_study.sh" "$EXTRA"
"$REPO_DIR/scripts/test_demo.sh" "$EXTRA"
"$REPO_DIR/scripts/test_node_startup.sh" "$EXTRA"
"$REPO_DIR/scripts/test_live_replay.sh" "$EXTRA"
"$REPO_DIR/scripts/test_campaign_slurm.sh" "$EXTRA"

echo "=== summary ==="
/usr/bin/python3 "$REPO_DIR/scripts/summarize_tests.py" "$RESULTS" "$EXTRA"

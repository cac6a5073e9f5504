#!/usr/bin/env bash
# The gtest unit tests under AddressSanitizer (with LeakSanitizer) and
# UndefinedBehaviorSanitizer: builds them with clang and PPP_SANITIZE=ON in their own
# build directory, runs each executable and counts every sanitizer report as a finding.
#  * With catkin: one catkin workspace build_sanitize/ws (git-ignored) builds the core
#    units (test/core, test/integration, test/data), the integrity units
#    (test/integrity/test_*, integrity_live_unit) and the ROS adapter units that need no
#    roscore (test/ros). One build serves all of them: the core is compiled once.
#  * Without catkin, or with PPP_SANITIZE_CORE_ONLY=1: plain CMake with PPP_CORE_ONLY=ON
#    in build_sanitize/core, the core and integrity units only.
# Reports of the sanitizers (also those of the tools a test starts) are written to
# build_sanitize/findings/<test>.{asan,ubsan}.<pid>; each test's output to
# build_sanitize/logs/<test>.log. A test passes when it exits 0 and left no report.
# Writes one JUnit result per test executable (sanitize-<test>.xml) into the directory
# given as $1 (default build_sanitize/results), prints the findings and closes with
# "N passed, N failed, N skipped"; exits 1 when anything failed.
# Environment: PPP_SANITIZE_DIR (build_sanitize), PPP_SANITIZE_TIMEOUT_S (seconds per
# test executable, 900; a test over it is skipped with the count of its cases that
# passed), PPP_SANITIZE_EXCLUDE (gtest patterns joined by ':' to leave out; none by default), PPP_SANITIZE_ONLY (space-separated test names to run),
# PPP_SANITIZE_NO_BUILD=1 (run what is built), PPP_SHARED_DATA, PPP_JOBS.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
SAN_DIR="${PPP_SANITIZE_DIR:-$REPO_DIR/build_sanitize}"
OUT="${1:-$SAN_DIR/results}"
TIMEOUT_S="${PPP_SANITIZE_TIMEOUT_S:-900}"
FINDINGS="$SAN_DIR/findings"
LOGS="$SAN_DIR/logs"
SUPP_DIR="$REPO_DIR/test/sanitizers"

# Test cases left out of every executable (gtest patterns), with
# the reason. None by default: PPP_SANITIZE_EXCLUDE="*PatternA*:*PatternB*" leaves some out.
EXCLUDED=()
if [ -n "${PPP_SANITIZE_EXCLUDE:-}" ]; then
  IFS=: read -r -a patterns <<< "$PPP_SANITIZE_EXCLUDE"
  for p in "${patterns[@]}"; do [ -n "$p" ] && EXCLUDED+=("$p|left out by PPP_SANITIZE_EXCLUDE"); done
fi

junit() { write_junit "$OUT/sanitize-$1.xml" sanitizers "$1" "$2" "$3"; }  # name status message

# unit_test_names: the gtest executables of the repository (one per source file).
# The same files as CMakeLists.txt: test/core (with its part folders), test/integration,
# test/data, test/integrity and, with catkin, test/ros.
unit_test_names() {
  local files=() f
  mapfile -t files < <(find "$REPO_DIR"/test/core "$REPO_DIR"/test/integration "$REPO_DIR"/test/data \
                         -name 'test_*.cpp' -type f 2>/dev/null | sort)
  files+=("$REPO_DIR"/test/integrity/test_*.cpp)
  [ "$MODE" = catkin ] && files+=("$REPO_DIR"/test/ros/test_*.cpp)
  for f in "${files[@]}"; do basename "$f" .cpp; done
  [ "$MODE" = catkin ] && echo integrity_live_unit
}

# build_catkin TARGETS...: the clang + sanitizer catkin workspace (scripts/build.sh).
build_catkin() {
  PPP_WS_DIR="$SAN_DIR/ws" "$REPO_DIR/scripts/build.sh" -DPPP_SANITIZE=ON -DCATKIN_ENABLE_TESTING=ON \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ "${LAUNCHER[@]}" "$@"
}

# build_core TARGETS...: the clang + sanitizer plain CMake build of the core.
build_core() {
  cmake -S "$REPO_DIR" -B "$SAN_DIR/core" -DPPP_CORE_ONLY=ON -DPPP_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    "${LAUNCHER[@]}" && make -C "$SAN_DIR/core" -j"$JOBS" "$@"
}

# excluded_filter: the gtest negative filter of the excluded cases (or nothing).
excluded_filter() {
  local e p filter=""
  for e in "${EXCLUDED[@]}"; do p="${e%%|*}"; filter="${filter:+$filter:}$p"; done
  echo "$filter"
}

# run_one NAME: runs one test executable; sets RESULT (passed|failed|skipped) and WHY.
run_one() {
  local name="$1" exe filter rc reports
  exe=$(find "$BUILD_ROOT" -type f -name "$name" -perm -u+x 2>/dev/null | head -1)
  if [ -z "$exe" ]; then RESULT=failed; WHY="executable not built"; return; fi
  filter=$(excluded_filter)
  rm -f "$FINDINGS/$name".*
  (cd "$REPO_DIR" && \
    ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:log_path=$FINDINGS/$name.asan" \
    UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$FINDINGS/$name.ubsan:suppressions=$SUPP_DIR/ubsan.supp" \
    LSAN_OPTIONS="suppressions=$SUPP_DIR/lsan.supp" \
    timeout -k 10 "$TIMEOUT_S" "$exe" ${filter:+--gtest_filter="-$filter"} > "$LOGS/$name.log" 2>&1)
  rc=$?
  reports=$(ls "$FINDINGS/$name".* 2>/dev/null)
  if [ -n "$reports" ]; then
    RESULT=failed
    WHY="$(grep -h -m1 -E '^SUMMARY: ' $reports | head -1) ($(echo "$reports" | wc -l) report(s))"
  elif [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
    RESULT=skipped
    WHY="time budget of ${TIMEOUT_S} s reached after $(grep -c -E '^\[ +OK \]' "$LOGS/$name.log") passed case(s), no report in them"
  elif [ $rc -ne 0 ]; then
    RESULT=failed; WHY="exit $rc: $(grep -m1 -E '^\[  FAILED  \]' "$LOGS/$name.log")"
  else
    RESULT=passed; WHY=""
  fi
}

if ! command -v clang++ > /dev/null; then
  echo "test_sanitizers: clang++ not installed"; echo "0 passed, 1 failed, 0 skipped"; exit 1
fi
MODE=core
if [ "${PPP_SANITIZE_CORE_ONLY:-0}" != 1 ] && command -v catkin_make > /dev/null; then MODE=catkin; fi
LAUNCHER=()
command -v ccache > /dev/null && LAUNCHER=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
mkdir -p "$OUT" "$FINDINGS" "$LOGS"
export PPP_SHARED_DATA="$SHARED_DATA"
if [ -n "${PPP_SANITIZE_ONLY:-}" ]; then read -r -a TESTS <<< "$PPP_SANITIZE_ONLY"; else mapfile -t TESTS < <(unit_test_names); fi

if [ "$MODE" = catkin ]; then BUILD_ROOT="$SAN_DIR/ws"; else BUILD_ROOT="$SAN_DIR/core"; fi
if [ "${PPP_SANITIZE_NO_BUILD:-0}" != 1 ]; then
  echo "=== build ($MODE, clang, ASan + UBSan) into $BUILD_ROOT ==="
  start=$SECONDS
  # With the tools the units start as child processes (bag, campaign and solve tests).
  if [ "$MODE" = catkin ]; then build_catkin "${TESTS[@]}" ppp_solve ppp_to_bag ppp_bag_solve ppp_campaign;
  else build_core "${TESTS[@]}"; fi \
    > "$SAN_DIR/build.log" 2>&1
  rc=$?
  echo "test_sanitizers: build exit $rc in $((SECONDS - start)) s (log $SAN_DIR/build.log)"
  [ $rc -ne 0 ] && tail -30 "$SAN_DIR/build.log"
fi

# The sanitized workspace's environment: units that start roslaunch find this package there.
if [ "$MODE" = catkin ] && [ -f "$BUILD_ROOT/devel/setup.bash" ]; then
  set +u; source "$BUILD_ROOT/devel/setup.bash"; set -u
fi
echo "=== run (shared data: $SHARED_DATA) ==="
passed=0; failed=0; skipped=0; run_start=$SECONDS
for name in "${TESTS[@]}"; do
  t0=$SECONDS
  run_one "$name"
  junit "$name" "$RESULT" "$WHY"
  case "$RESULT" in passed) passed=$((passed + 1)) ;; failed) failed=$((failed + 1)) ;; *) skipped=$((skipped + 1)) ;; esac
  printf 'test_sanitizers: %-45s %-7s %4d s %s\n' "$name" "$RESULT" $((SECONDS - t0)) "$WHY"
done
echo "test_sanitizers: ran in $((SECONDS - run_start)) s"

echo "=== excluded ==="
for e in "${EXCLUDED[@]}"; do echo "  ${e%%|*}: ${e#*|}"; done
echo "=== cases over 10 s ==="
for name in "${TESTS[@]}"; do
  grep -h -E '^\[ +OK \] .* \(([0-9]{5,}) ms\)$' "$LOGS/$name.log" 2>/dev/null | sed "s/^/  $name: /"
done
echo "=== findings ==="
found=0
for name in "${TESTS[@]}"; do
  for f in "$FINDINGS/$name".*; do
    [ -e "$f" ] || continue
    found=$((found + 1))
    echo "--- $f"
    grep -m1 -E 'ERROR: |runtime error' "$f"
    grep -m3 -E "^ +#[0-9]+ .*$REPO_DIR/(src|include|test)/" "$f"
  done
done
echo "$found sanitizer report(s)"
echo "$passed passed, $failed failed, $skipped skipped"
[ $failed -eq 0 ]

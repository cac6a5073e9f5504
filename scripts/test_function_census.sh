#!/usr/bin/env bash
# Script test of scripts/function_census.py: runs its unit test
# (test/scripts/test_function_census.py, small C++ texts whose functions and lengths
# are known by reading them) and a census of src/ that must find functions.
# Writes one JUnit result into the directory given as $1 (scripts/test.sh's extra dir).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin function_census "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

LOG="$WORK/census.log"
fail=""
/usr/bin/python3 "$REPO_DIR/test/scripts/test_function_census.py" > "$LOG" 2>&1 || fail+="unit test failed: $(tail -1 "$LOG"); "
/usr/bin/python3 "$REPO_DIR/scripts/function_census.py" >> "$LOG" 2>&1 || fail+="census of src/ exited non-zero; "
grep -qE '^functions: [1-9][0-9]*$' "$LOG" || fail+="census of src/ found no functions; "
if [[ -n "$fail" ]]; then
  junit failed "$fail"
  echo "test_function_census: FAILED: $fail"; cat "$LOG"
else
  junit passed ""
  echo "test_function_census: ok"
fi

#!/usr/bin/env bash
# Script test of scripts/nl_residual_histogram.py on a small synthetic narrow-lane CSV
# (the columns ppp_ar_study --nl-csv writes), with values known by hand:
#  * GPS: four held single differences, float minus held +0.1, -0.1, +0.1, -0.1 cycle at
#    sigma 0.1: mean +0.000, sd sqrt(4 * 0.01 / 3) = 0.115, RMS 0.100, all within 0.15,
#    RMS(residual / sigma) 1.00; histogram: half in the bin from -0.10, half from +0.10;
#  * Galileo: two held at +0.3 cycle, sigma 0.1: mean +0.300, RMS 0.300, none within 0.15,
#    RMS(residual / sigma) 3.00;
#  * a row without a held integer is not counted.
# Writes one JUnit result into the directory given as $1 (scripts/test.sh's extra dir).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin nl_residual_histogram "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

cat > "$WORK/nl.csv" << 'CSV'
time_s,satellite,reference,wide_lane,float_cycles,sigma_cycles,held_cycles
100,G07,G05,5,18.1,0.1,18
100,G13,G05,3,4.9,0.1,5
130,G07,G05,5,18.1,0.1,18
130,G13,G05,3,4.9,0.1,5
130,G20,G05,2,7.45,0.6,
100,E11,E12,-1,-2.7,0.1,-3
130,E11,E12,-1,-2.7,0.1,-3
CSV
/usr/bin/python3 "$REPO_DIR/scripts/nl_residual_histogram.py" "t=$WORK/nl.csv" > "$WORK/out.md" 2> "$WORK/err.txt"
rc=$?
fail=""
[ $rc -eq 0 ] || fail+="exit $rc: $(head -c 300 "$WORK/err.txt"); "
grep -qF "| t | GPS | 4 | +0.000 | 0.115 | 0.100 | 0.100 | 100.0 % | 0.100 | 1.00 |" "$WORK/out.md" || fail+="GPS row; "
grep -qF "| t | Galileo | 2 | +0.300 | 0.000 | 0.300 | 0.300 | 0.0 % | 0.100 | 3.00 |" "$WORK/out.md" || fail+="Galileo row; "
gps_hist=$(grep -F "| t | GPS | 0.0" "$WORK/out.md")
[ "$(echo "$gps_hist" | awk -F'|' '{print $12, $16}')" = " 50.0   50.0 " ] || fail+="GPS histogram ($gps_hist); "
printf 'time_s,satellite,reference,wide_lane,float_cycles,sigma_cycles,held_cycles\n1,G01,G02,1,abc,0.1,3\n' > "$WORK/bad.csv"
/usr/bin/python3 "$REPO_DIR/scripts/nl_residual_histogram.py" "t=$WORK/bad.csv" > /dev/null 2> "$WORK/bad.txt"
[ $? -ne 0 ] && grep -qF "$WORK/bad.csv: line 2:" "$WORK/bad.txt" || fail+="a non-numeric float is not refused with the file and line named; "
if [ -z "$fail" ]; then
  junit passed ""
  echo "test_nl_residual_histogram: passed"
else
  junit failed "$fail"
  echo "test_nl_residual_histogram: FAILED: $fail"; cat "$WORK/out.md"
fi

#!/usr/bin/env bash
# Script test of scripts/plot_solutions.py: runs it on small synthetic CSVs (two
# solutions of 40 epochs at 30 s, one bias file of two arcs) and checks that the
# three PNGs are written and that the printed numbers are the known ones:
#  * solution "a" has 3D errors 1..40 cm, so its median over all epochs is
#    20.50 cm (linear interpolation between 20 and 21) and its maximum 40.00 cm;
#  * its first 15 min are the epochs with t - t0 < 900 s (as position_error_statistics.h:
#    30 epochs, 1..30 cm): median 15.50 cm;
#  * arc G01 1 starts 30 cm above its final smoothed value and stays within 5 cm
#    of it from minute 10 on;
#  * residuals of G01 (41 rows, the last with blank postfits: not used): code postfit
#    alternating 0.10 / 0.30 m -> mean 20.0 cm, RMS sqrt((0.01 + 0.09) / 2) m = 22.4 cm;
#    phase 3 mm at every used row -> mean 3.0, RMS 3.0 mm; elevation 10..50 deg -> mean 30.0.
# Writes one JUnit result into the directory given as $1 (scripts/test.sh's extra dir).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
script_test_begin plot_solutions "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE

if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  junit skipped "python3-matplotlib not installed"
  echo "test_plot_solutions: skipped (no matplotlib)"
  exit 0
fi

# Synthetic inputs (only the columns the script reads, plus an empty "no solution" row).
/usr/bin/python3 - "$WORK" <<'PY'
import datetime as dt, sys
work = sys.argv[1]
t0 = dt.datetime(2026, 5, 13)
for name, scale in (("a", 1.0), ("b", 0.5)):
    with open(f"{work}/{name}.csv", "w") as f:
        f.write("gps_week,tow_s,time_gpst,err3d_m,status\n")
        for k in range(40):
            t = (t0 + dt.timedelta(seconds=30 * k)).isoformat(timespec="milliseconds")
            f.write(f"2418,{259200 + 30 * k},{t},{scale * (k + 1) / 100:.4f},ppp-float\n")
        t = (t0 + dt.timedelta(seconds=1200)).isoformat(timespec="milliseconds")
        f.write(f"2418,{259200 + 1200},{t},,no-solution\n")
with open(f"{work}/biases.csv", "w") as f:
    f.write("time_gpst,arc,sat,bias_m,sigma_m,smoothed_final_m\n")
    for k in range(40):
        t = (t0 + dt.timedelta(seconds=30 * k)).isoformat(timespec="milliseconds")
        f.write(f"{t},1,G01,{1.0 + (0.30 if k < 20 else 0.01):.4f},0.1,1.0000\n")
        f.write(f"{t},2,G02,{-2.0 + 0.001 * k:.4f},0.1,-2.0000\n")
with open(f"{work}/residuals.csv", "w") as f:
    f.write("time_gpst,sat,arc,new_arc,elevation_deg,azimuth_deg,code_prefit_m,phase_prefit_m,code_postfit_m,phase_postfit_m,code_sigma_m,phase_sigma_m\n")
    for k in range(40):
        t = (t0 + dt.timedelta(seconds=30 * k)).isoformat(timespec="milliseconds")
        f.write(f"{t},G01,1,0,{10 + k},0,0,0,{0.10 if k % 2 == 0 else 0.30:.2f},0.003,1,0.01\n")
    t = (t0 + dt.timedelta(seconds=30 * 40)).isoformat(timespec="milliseconds")
    f.write(f"{t},G01,1,0,50,0,0,0,,,1,0.01\n")
PY

LOG="$WORK/plot.log"
if ! /usr/bin/python3 "$REPO_DIR/scripts/plot_solutions.py" --out "$WORK/png" a="$WORK/a.csv" b="$WORK/b.csv" \
     --biases s="$WORK/biases.csv" --residuals r="$WORK/residuals.csv" > "$LOG" 2>&1; then
  junit failed "plot_solutions.py exited non-zero: $(tail -1 "$LOG")"
  cat "$LOG"; exit 0
fi
fail=""
for png in error_profile cdf biases residuals_r; do
  f="$WORK/png/$png.png"
  # A PNG starts with the 8-byte signature 89 50 4E 47 0D 0A 1A 0A (PNG spec 5.2).
  [[ -s "$f" && "$(head -c 4 "$f" | od -An -tx1 | tr -d ' \n')" == "89504e47" ]] || fail+="$png.png missing or not a PNG; "
done
grep -qE '^a +all +20\.50 .* 40\.00$' "$LOG" || fail+="median/max of a over all epochs not 20.50/40.00; "
grep -qE '^a +15 min +15\.50 ' "$LOG" || fail+="median of a over the first 15 min not 15.50; "
grep -qE '^s +G01 1 +40 +30\.0 +1\.0 +10\.0$' "$LOG" || fail+="bias arc G01 1 figures not 30.0 / 1.0 / 10.0 min; "
grep -qE '^r +G01 +41 +30\.0 +20\.0 +22\.4 +3\.0 +3\.0$' "$LOG" || fail+="residual statistics of G01 not 41 / 30.0 / 20.0 / 22.4 / 3.0 / 3.0; "
if [[ -n "$fail" ]]; then
  junit failed "$fail"
  echo "test_plot_solutions: FAILED: $fail"; cat "$LOG"
else
  junit passed ""
  echo "test_plot_solutions: ok (4 PNGs written, figures as expected)"
fi

#!/usr/bin/env bash
# Script test of ppp_campaign on a real single-node Slurm cluster started here
# (scripts/slurm_local.sh: munged, slurmctld and slurmd of Debian's slurm-wlm,
# 2 CPUs, stopped at exit), against the local process pool:
#  1. a manifest naming a missing file is refused before anything runs: exit 2,
#     the file named, no output directory, nothing queued;
#  2. a 6-job campaign over the shared datasets (ZIM2, CCJ2, ESBC hours 0-3) run by
#     the local pool and by Slurm (3 array tasks for 2 jobs each) writes the same bytes (every job
#     output, marker and the summary files; only timing.json, the logs and slurm/ differ), and every
#     job was taken by exactly one of the array's tasks;
#  2b. the same campaign plus a long job (ESBC whole day, smoother) in the local pool:
#     the long job's process is killed mid-run (SIGKILL): the campaign ends with it
#     failed (the signal named) and the others done; the next invocation runs that
#     job only (the others' markers untouched) and ends done;
#  3. the same seven jobs on Slurm with no resubmission; the long task is cancelled
#     mid-run (scancel): the campaign ends with it failed (the Slurm state named) and
#     the others done; the next invocation runs that job only (the others' markers
#     untouched) and ends done;
#     with one resubmission allowed, the same cancellation is resubmitted and done in
#     the same invocation; a SIGTERM to the campaign cancels its array (exit 143, the
#     stopped jobs' reasons name the signal, nothing resubmitted or left queued);
#     a campaign killed with -9 leaves no array behind: its tasks cancel the array
#     once the campaign's heartbeat is older than the lease;
#  4. a Monte Carlo study of 40 flights (2 min, GPS + Galileo) as 4 shards through
#     Slurm equals one 40-flight ppp_monte_carlo run with the same seed: the CDF,
#     error-versus-time, bias-convergence and representative-flight tables byte for
#     byte, summary.json and flights.csv apart from the wall-clock fields.
# Skips (with the reason) without the shared datasets or when Slurm cannot run here
# (not root, slurm-wlm/munge missing). Writes one JUnit result into $1.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
source "$REPO_DIR/scripts/slurm_local.sh"
script_test_begin campaign_slurm "${1:-}"   # OUT, WORK (removed at exit), junit STATUS MESSAGE
trap 'stop_local_slurm; rm -rf "$WORK"' EXIT

CAMPAIGN="$BIN_DIR/ppp_campaign"
D="$SHARED_DATA"
if [ ! -x "$CAMPAIGN" ] || [ ! -x "$BIN_DIR/ppp_monte_carlo" ]; then
  junit failed "ppp_campaign or ppp_monte_carlo not built in $BIN_DIR"; exit 0
fi
if [ ! -d "$D/esbc-2020-177" ] || [ ! -d "$D/zim2-2026-133" ]; then
  junit skipped "shared datasets not found at $D"; echo "test_campaign_slurm: skipped (no data)"; exit 0
fi
start_local_slurm "$WORK/slurm" 2
rc=$?
if [ $rc -eq 2 ]; then
  junit skipped "Slurm cannot run here: $SLURM_SKIP_REASON"; echo "test_campaign_slurm: skipped: $SLURM_SKIP_REASON"; exit 0
elif [ $rc -ne 0 ]; then
  junit failed "the local Slurm cluster did not come up: $(tail -3 "$WORK"/slurm/log/*.log 2>/dev/null | tr '\n' ' ')"; exit 0
fi
echo "test_campaign_slurm: Slurm up ($SLURM_CONF)"

fail=""
note() { fail="$fail; $*"; echo "test_campaign_slurm: FAIL: $*"; }

jobs_yaml() {  # the 6 jobs
  cat << EOF
campaign: {name: shared6, data_root: $D}
slurm: {time_limit: "00:10:00", mem: "500M", max_resubmits: 0}
ppp:
  - station: zim2
    obs: zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx
    sp3: [zim2-2026-133/IGS0OPSFIN_20261330000_03H_15M_ORB.SP3]
    clk: [zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK]
    bia: zim2-2026-133/COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz
    atx: [antex/igs20_zim2_gps_trim.atx]
    blq: oceanload/zim2_fes2004.blq
    truth: [4331299.5841, 567537.7070, 4633133.9645]
  - station: ccj2
    obs: "ccj2-2021-210/ccj2{doy}0.{yy}o"
    dates: {first: 2021-07-29, last: 2021-07-29}
    sp3: ["ccj2-2021-210/WUM0MGXRAP_{yyyy}{doy}0000_01D_01M_ORB.SP3.gz"]
    clk: ["ccj2-2021-210/WUM0MGXRAP_{yyyy}{doy}0000_01D_30S_CLK.CLK.gz"]
    atx: [antex/igs14_2178_satellites.atx, antex/igs20_zim2_gps_trim.atx]
    blq: oceanload/ccj2_fes2004.blq
    truth: [-4490605.094, 3483895.065, 2884928.334]
  - station: esbc
    obs: esbc-2020-177/ESBC00DNK_R_*_01D_30S_MO.crx.gz
    dates: {first: 2020-06-25, last: 2020-06-25}
    hours: [0, 3]
    sp3: [esbc-2020-177/GRG0MGXFIN_*_ORB.SP3.gz]
    clk: [esbc-2020-177/GRG0MGXFIN_*_CLK.CLK.gz]
    atx: [antex/igs14_2178_satellites.atx, antex/igs05_esbc_receiver_trim.atx]
    blq: oceanload/esbc_fes2014b.blq
EOF
}
long_job_yaml() {  # a job long enough to be cancelled mid-run
  cat << EOF
  - station: esbcday
    obs: esbc-2020-177/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz
    sp3: [esbc-2020-177/GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz]
    clk: [esbc-2020-177/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz]
    atx: [antex/igs14_2178_satellites.atx, antex/igs05_esbc_receiver_trim.atx]
    estimator: both
EOF
}
jobs_yaml > "$WORK/six.yaml"
{ jobs_yaml; long_job_yaml; } > "$WORK/seven.yaml"

# 1. A missing file: refused up front, nothing created, nothing queued.
{ jobs_yaml; echo "  - {station: lost, obs: zim2-2026-133/ZIM200CHE_R_20261330000_01H_30S_MO.rnx, sp3: [zim2-2026-133/NO_SUCH.SP3], clk: [zim2-2026-133/IGS0OPSFIN_20261330000_90M_30S_CLK.CLK], atx: [antex/igs20_zim2_gps_trim.atx]}"; } > "$WORK/missing.yaml"
"$CAMPAIGN" run "$WORK/missing.yaml" --out "$WORK/missing" --slurm --no-plot > "$WORK/missing.log" 2>&1
rc=$?
[ $rc -eq 2 ] || note "a manifest with a missing file exited $rc (2 expected)"
grep -q "job lost: sp3 $D/zim2-2026-133/NO_SUCH.SP3: no such file" "$WORK/missing.log" || note "the missing file is not named: $(head -3 "$WORK/missing.log")"
[ ! -e "$WORK/missing" ] || note "the refused campaign created its output directory"
[ -z "$(squeue -h 2>/dev/null)" ] || note "the refused campaign queued something: $(squeue -h)"

# 2. The 6 jobs, local pool and Slurm: the same bytes.
t0=$(date +%s.%N)
"$CAMPAIGN" run "$WORK/six.yaml" --out "$WORK/local" --local --jobs 2 --no-plot > "$WORK/local.log" 2>&1 || note "local campaign exited $?: $(tail -3 "$WORK/local.log")"
t1=$(date +%s.%N)
"$CAMPAIGN" run "$WORK/six.yaml" --out "$WORK/slurm6" --slurm --jobs-per-task 2 --poll-s 0.3 --no-plot > "$WORK/slurm6.log" 2>&1 || note "slurm campaign exited $?: $(tail -3 "$WORK/slurm6.log")"
t2=$(date +%s.%N)
awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN {printf "test_campaign_slurm: 6 jobs local %.1f s, slurm %.1f s\n", b - a, c - b}'
n_done=$(ls "$WORK"/slurm6/jobs/*/done.json 2>/dev/null | wc -l)
[ "$n_done" -eq 6 ] || note "slurm: $n_done of 6 jobs done"
grep -q "submitted array job" "$WORK/slurm6.log" || note "the slurm run did not submit an array job"
if ! diff -r -q -x timing.json -x log.txt -x slurm -x summary.png "$WORK/local" "$WORK/slurm6" > "$WORK/diff.txt"; then
  note "local and slurm outputs differ: $(head -5 "$WORK/diff.txt" | tr '\n' ' ')"
fi
n_files=$(find "$WORK/slurm6/jobs" -path '*/output/*' -type f | wc -l)
[ "$n_files" -ge 30 ] || note "only $n_files output files compared"
# every line of the job list taken by exactly one of the 3 array tasks
claims="$WORK/slurm6/slurm/round0.claims"
n_claims=$(ls "$claims" 2>/dev/null | grep -c '^[0-9][0-9]*$')
[ "$n_claims" -eq 6 ] && [ "$(cat "$claims/next" 2>/dev/null)" = "6" ] || note "slurm: $n_claims claims of the 6 list lines (next: $(cat "$claims/next" 2>/dev/null))"
outside=$(cat "$claims"/[0-9]* 2>/dev/null | grep -cvE '^[1-3]$')
[ "$outside" -eq 0 ] || note "slurm: claims by tasks outside the array of 3: $(cat "$claims"/[0-9]* | tr '\n' ' ')"

# 2b and 3: a campaign of the seven jobs whose long job was stopped mid-run (its
# process killed, its Slurm task cancelled), then run again.
check_stopped_long_job() {  # LABEL OUT RC REASON: the campaign exited RC; BEFORE = the other jobs' marker times
  local label="$1" out="$2" rc="$3" reason="$4"
  [ "$rc" -eq 1 ] || note "$label: the campaign with a stopped job exited $rc (1 expected)"
  [ ! -e "$out/jobs/esbcday/done.json" ] || note "$label: the stopped job has a finished marker"
  grep -q "$reason" "$out/jobs/esbcday/failed.json" 2>/dev/null || note "$label: the stopped job's reason does not name '$reason': $(cat "$out/jobs/esbcday/failed.json" 2>/dev/null)"
  grep -q "esbcday,ppp,esbcday,,,failed" "$out/summary.csv" 2>/dev/null || note "$label: the summary does not list the stopped job as failed"
  BEFORE=$(stat -c '%n %y' "$out"/jobs/{zim2,ccj2_*,esbc_*}/done.json 2>/dev/null | sort)
  [ "$(echo "$BEFORE" | wc -l)" -eq 6 ] || note "$label: the other 6 jobs did not all finish: $(cat "$out/summary.csv" 2>/dev/null)"
}
check_rerun_of_long_job() {  # LABEL OUT LOG: the re-run (logged in LOG) ran the stopped job only
  local label="$1" out="$2" log="$3"
  grep -q "7 jobs: 6 already done, 1 to run" "$log" || note "$label: the re-run did not run exactly the stopped job: $(grep 'already done' "$log")"
  [ "$BEFORE" = "$(stat -c '%n %y' "$out"/jobs/{zim2,ccj2_*,esbc_*}/done.json 2>/dev/null | sort)" ] || note "$label: the re-run touched finished jobs"
  [ -f "$out/jobs/esbcday/done.json" ] || note "$label: the stopped job did not finish on the re-run"
}

# 2b. The local pool: the long job's process killed mid-run; the next invocation runs that job only.
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/localkill" --local --jobs 2 --no-plot > "$WORK/localkill.log" 2>&1 &
campaign_pid=$!
killed=""
for i in $(seq 1 300); do
  job_pid=$(pgrep -f "run-job $WORK/localkill/jobs/esbcday\$" | head -1)
  if [ -n "$job_pid" ]; then sleep 0.5; kill -KILL "$job_pid" && killed="$job_pid"; break; fi
  sleep 0.1
done
wait "$campaign_pid"
rc=$?
[ -n "$killed" ] || note "local: the long job's process was never seen running"
check_stopped_long_job local "$WORK/localkill" $rc "run-job killed by signal 9"
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/localkill" --local --jobs 2 --no-plot > "$WORK/localrerun.log" 2>&1 || note "local: the re-run exited $?: $(tail -3 "$WORK/localrerun.log")"
check_rerun_of_long_job local "$WORK/localkill" "$WORK/localrerun.log"

# 3. Cancel a running task; the next invocation runs that job only.
cancel_long_task() {  # OUT_DIR: cancels the esbcday task of round 0 once it runs; CANCELLED = its task id
  local list="$1/slurm/round0.list" i k id task
  CANCELLED=""
  for i in $(seq 1 300); do
    if [ -f "$list" ]; then
      k=$(grep -n '/esbcday$' "$list" | cut -d: -f1)
      id=$(cat "$1/slurm/round0.claims/$k" 2> /dev/null)  # the array task that took list line k
      task=""
      [ -n "$id" ] && task=$(squeue -h -r -o '%i %T' 2>/dev/null | awk -v k="_$id" '$1 ~ k"$" && $2 == "RUNNING" {print $1}')
      if [ -n "$task" ]; then sleep 0.5; scancel "$task" && CANCELLED="$task"; return; fi
    fi
    sleep 0.1
  done
}
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/kill" --slurm --poll-s 0.3 --max-resubmits 0 --no-plot > "$WORK/kill.log" 2>&1 &
campaign_pid=$!
cancel_long_task "$WORK/kill"
cancelled="$CANCELLED"
wait "$campaign_pid"
rc=$?
[ -n "$cancelled" ] || note "slurm: the long task was never seen running"
check_stopped_long_job slurm "$WORK/kill" $rc "CANCELLED"
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/kill" --slurm --poll-s 0.3 --no-plot > "$WORK/rerun.log" 2>&1 || note "slurm: the re-run exited $?: $(tail -3 "$WORK/rerun.log")"
check_rerun_of_long_job slurm "$WORK/kill" "$WORK/rerun.log"
cmp -s "$WORK/kill/jobs/esbc_2020-177_h02/output/esbc_ekf.csv" "$WORK/local/jobs/esbc_2020-177_h02/output/esbc_ekf.csv" || note "resumed outputs differ from the local run"

# 3b. With resubmission: the cancelled task is resubmitted within the same invocation.
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/resubmit" --slurm --poll-s 0.3 --max-resubmits 1 --no-plot > "$WORK/resubmit.log" 2>&1 &
campaign_pid=$!
cancel_long_task "$WORK/resubmit"
wait "$campaign_pid"
rc=$?
[ -n "$CANCELLED" ] || note "resubmission: the long task was never seen running"
[ $rc -eq 0 ] || note "resubmission: the campaign exited $rc (0 expected: the cancelled job resubmitted and done)"
grep -q "resubmitting 1 job(s)" "$WORK/resubmit.log" || note "resubmission: no resubmission of the cancelled job: $(grep ppp_campaign "$WORK/resubmit.log" | tail -3)"
[ -f "$WORK/resubmit/jobs/esbcday/done.json" ] || note "resubmission: the cancelled job is not done"
[ "$(ls "$WORK"/resubmit/slurm/round*.list | wc -l)" -eq 2 ] || note "resubmission: not exactly two submissions"

# 3c. A stop signal to the campaign cancels its array: the running job is marked failed with
#     the signal named, nothing stays queued, the exit status is 128 + 15.
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/stop" --slurm --poll-s 0.3 --max-resubmits 1 --no-plot > "$WORK/stop.log" 2>&1 &
campaign_pid=$!
for i in $(seq 1 300); do
  if [ -f "$WORK/stop/slurm/round0.list" ] && [ -n "$(squeue -h -t RUNNING 2>/dev/null)" ]; then break; fi
  sleep 0.1
done
sleep 0.5
kill -TERM "$campaign_pid"
wait "$campaign_pid"
rc=$?
[ $rc -eq 143 ] || note "stop: the campaign stopped by SIGTERM exited $rc (143 expected)"
grep -q "cancelling array job" "$WORK/stop.log" || note "stop: the array was not cancelled: $(tail -3 "$WORK/stop.log")"
grep -q "the campaign was stopped by signal 15" "$WORK"/stop/jobs/*/failed.json 2>/dev/null || note "stop: no job marked failed with the signal named"
for i in $(seq 1 50); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.2; done
[ -z "$(squeue -h 2>/dev/null)" ] || note "stop: tasks stayed queued after the stop: $(squeue -h)"
[ "$(ls "$WORK"/stop/slurm/round*.list | wc -l)" -eq 1 ] || note "stop: a stopped campaign resubmitted"

# 3d. A campaign killed with -9 cannot cancel its array: the tasks see its heartbeat
#     go stale and cancel the array themselves within the lease (4 s here), the running
#     long job included; nothing stays queued and the job is not done.
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/orphan" --slurm --poll-s 0.3 --lease-s 4 --max-resubmits 0 --no-plot > "$WORK/orphan.log" 2>&1 &
campaign_pid=$!
for i in $(seq 1 300); do
  if [ -f "$WORK/orphan/slurm/round0.list" ] && [ -n "$(squeue -h -t RUNNING 2>/dev/null)" ]; then break; fi
  sleep 0.1
done
sleep 0.5
kill -KILL "$campaign_pid"
wait "$campaign_pid" 2> /dev/null
killed_at=$(date +%s)
for i in $(seq 1 300); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.2; done
left_s=$(( $(date +%s) - killed_at ))
echo "test_campaign_slurm: the orphaned array left the queue ${left_s} s after its campaign was killed"
[ -z "$(squeue -h 2>/dev/null)" ] || { note "orphan: the array of a campaign killed with -9 stayed queued: $(squeue -h | head -3)"; scancel --user="$(id -un)" 2>/dev/null; }
[ "$left_s" -le 30 ] || note "orphan: the array took ${left_s} s to leave the queue (lease 4 s)"
grep -q "no campaign watches array" "$WORK"/orphan/slurm/*.log 2>/dev/null || note "orphan: no task log names the stale heartbeat"
[ ! -e "$WORK/orphan/jobs/esbcday/done.json" ] || note "orphan: the long job finished although its campaign was killed"
"$CAMPAIGN" run "$WORK/seven.yaml" --out "$WORK/orphan" --slurm --poll-s 1 --lease-s 2 --no-plot > "$WORK/orphan_lease.log" 2>&1
rc=$?
[ $rc -eq 2 ] && grep -q "lease-s (2 s) must be at least 3 looks" "$WORK/orphan_lease.log" || note "orphan: a lease shorter than 3 looks was not refused (exit $rc)"

# 4. Monte Carlo: 40 flights as 4 Slurm shards = one 40-flight run.
cat > "$WORK/mc.yaml" << EOF
campaign: {name: mc40}
slurm: {mem: "500M"}
monte_carlo:
  - {study: ge, seed: 5, flights: 40, flights_per_job: 10, duration_min: 2, systems: GE}
EOF
"$CAMPAIGN" run "$WORK/mc.yaml" --out "$WORK/mc" --slurm --poll-s 0.5 --no-plot > "$WORK/mc.log" 2>&1 || note "Monte Carlo campaign exited $?: $(tail -3 "$WORK/mc.log")"
"$BIN_DIR/ppp_monte_carlo" --flights 40 --seed 5 --duration-min 2 --systems GE --threads 2 --out "$WORK/mc_one" > "$WORK/mc_one.log" 2>&1 || note "ppp_monte_carlo exited $?"
for f in error_cdf.csv error_vs_time.csv bias_convergence.csv representative_flight.csv; do
  cmp -s "$WORK/mc_one/$f" "$WORK/mc/monte_carlo/ge/$f" || note "Monte Carlo $f: 4 shards differ from the one run"
done
/usr/bin/python3 - "$WORK/mc_one" "$WORK/mc/monte_carlo/ge" > "$WORK/mc_cmp.txt" 2>&1 << 'PY' || note "Monte Carlo summary differs: $(tail -2 "$WORK/mc_cmp.txt")"
import csv, json, sys
timing = {"threads", "wall_s", "simulate_s", "ekf_s", "smoother_s"}
a, b = (json.load(open(d + "/summary.json")) for d in sys.argv[1:])
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in timing}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
if strip(a) != strip(b):
    sys.exit("summary.json differs beyond the wall-clock fields")
rows = [list(csv.DictReader(open(d + "/flights.csv"))) for d in sys.argv[1:]]
if len(rows[0]) != 40 or [strip(r) for r in rows[0]] != [strip(r) for r in rows[1]]:
    sys.exit("flights.csv differs beyond the wall-clock columns")
print("same")
PY

if [ -z "$fail" ]; then
  junit passed ""
  echo "test_campaign_slurm: passed"
else
  junit failed "${fail#; }"
  echo "test_campaign_slurm: failed${fail}"
  for f in local slurm6 localkill localrerun kill rerun stop orphan mc; do echo "--- $f.log"; tail -15 "$WORK/$f.log" 2>/dev/null; done
fi
exit 0

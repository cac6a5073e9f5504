#!/usr/bin/env bash
# Benchmark of ppp_campaign (not a test; prints figures, writes nothing into the
# repository):
#  1. overhead: the 24 one-hour jobs of the ESBC day (GPS + Galileo, PPP-AR with
#     the GRG integer clocks; --estimator, default both) through the local pool
#     (--jobs 2) and through a private single-node Slurm cluster of 2 CPUs
#     (scripts/slurm_local.sh; needs root, slurm-wlm and munge), one job per array
#     task and --jobs-per-task (default 12: one task per CPU) jobs per task, each
#     --repeats times (default 3; slurmctld starts pending tasks on a one-second
#     tick, so single runs vary by up to a second): the wall times, their medians,
#     the ratios of the medians Slurm / local, and the mean job time;
#  2. Monte Carlo: N flights (default 1000; 30 min at 1 Hz, GPS + Galileo, the
#     method's simulation as ppp_monte_carlo runs it) as shards of 50 flights
#     through the local pool: wall time and flights per core-minute.
# usage: scripts/bench_campaign.sh [--flights N] [--estimator ekf|smoother|both] [--jobs-per-task K]
#                                   [--repeats R] [--skip-slurm] [--skip-mc]
# Run it niced on a shared machine: other load makes the figures noisy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
source "$REPO_DIR/scripts/slurm_local.sh"

FLIGHTS=1000
ESTIMATOR=both
PER_TASK=12
REPEATS=3
SKIP_SLURM=0
SKIP_MC=0
while [ $# -gt 0 ]; do
  case "$1" in
    --flights) FLIGHTS="$2"; shift 2 ;;
    --estimator) ESTIMATOR="$2"; shift 2 ;;
    --jobs-per-task) PER_TASK="$2"; shift 2 ;;
    --repeats) REPEATS="$2"; shift 2 ;;
    --skip-slurm) SKIP_SLURM=1; shift ;;
    --skip-mc) SKIP_MC=1; shift ;;
    *) echo "usage: $0 [--flights N] [--estimator ekf|smoother|both] [--jobs-per-task K] [--repeats R] [--skip-slurm] [--skip-mc]" >&2; exit 2 ;;
  esac
done
CAMPAIGN="$BIN_DIR/ppp_campaign"
[ -x "$CAMPAIGN" ] || { echo "bench_campaign: build first (no $CAMPAIGN)" >&2; exit 1; }
WORK="$(mktemp -d /tmp/ppp_bench_campaign.XXXXXX)"
trap 'stop_local_slurm; rm -rf "$WORK"' EXIT
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", b - a}'; }

cat > "$WORK/esbc24.yaml" << EOF
campaign: {name: esbc24, data_root: $SHARED_DATA}
slurm: {time_limit: "00:30:00", mem: "500M", max_resubmits: 0}
ppp:
  - station: esbc
    obs: "esbc-2020-177/ESBC00DNK_R_{yyyy}{doy}0000_01D_30S_MO.crx.gz"
    dates: {first: 2020-06-25, last: 2020-06-25}
    hours: [0, 23]
    sp3: ["esbc-2020-177/GRG0MGXFIN_{yyyy}{doy}0000_01D_15M_ORB.SP3.gz"]
    clk: ["esbc-2020-177/GRG0MGXFIN_{yyyy}{doy}0000_01D_30S_CLK.CLK.gz"]
    atx: [antex/igs14_2178_satellites.atx, antex/igs05_esbc_receiver_trim.atx]
    blq: oceanload/esbc_fes2014b.blq
    estimator: $ESTIMATOR
EOF

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
mean_job() { cat "$WORK/$1"/jobs/*/timing.json | sed 's/.*"wall_s": \([0-9.e+-]*\).*/\1/' | awk '{s += $1; n++} END {printf "%.3f", s / n}'; }
run_campaign() {  # OUT_NAME ARGS...: runs the 24 jobs; prints the wall time and the mean job time
  local name="$1" t0 t1
  shift
  rm -rf "$WORK/$name"
  t0=$(now)
  "$CAMPAIGN" run "$WORK/esbc24.yaml" --out "$WORK/$name" "$@" --no-plot > "$WORK/$name.log" 2>&1 \
    || echo "bench_campaign: the campaign $name failed: $(tail -3 "$WORK/$name.log")" >&2
  t1=$(now)
  echo "$(elapsed "$t0" "$t1") $(mean_job "$name")"
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.3f", b / a}'; }

# The runs alternate (local, Slurm with 1 job per task, Slurm with K), so that a
# drift of the machine's speed weighs on all of them alike; each repeat gives a
# ratio, and the median ratio is the figure.
if [ -d "$SHARED_DATA/esbc-2020-177" ]; then
  slurm_up=0
  if [ $SKIP_SLURM -eq 0 ]; then
    start_local_slurm "$WORK/slurm" 2
    rc=$?
    if [ $rc -eq 0 ]; then
      slurm_up=1
      run_campaign warmup --slurm --jobs-per-task 24 > /dev/null  # the cluster's first job pays its start-up
    else
      echo "overhead: Slurm not measured: ${SLURM_SKIP_REASON:-the cluster did not come up (see $WORK/slurm/log)}"
    fi
  fi
  declare -A ratios=()
  for r in $(seq 1 "$REPEATS"); do
    read -r local_s local_job <<< "$(run_campaign local --local --jobs 2)"
    line="overhead, repeat $r: local pool of 2 $local_s s (mean job $local_job s)"
    if [ $slurm_up -eq 1 ]; then
      for per_task in 1 $PER_TASK; do
        read -r slurm_s slurm_job <<< "$(run_campaign "slurm_$per_task" --slurm --jobs-per-task "$per_task")"
        ratios[$per_task]="${ratios[$per_task]:-} $(ratio "$local_s" "$slurm_s")"
        line="$line; Slurm $per_task/task $slurm_s s (mean job $slurm_job s)"
      done
    fi
    echo "$line"
  done
  echo "overhead: 24 one-hour ESBC jobs (estimator $ESTIMATOR) on 2 CPUs, $REPEATS repeats"
  if [ $slurm_up -eq 1 ]; then
    for per_task in 1 $PER_TASK; do
      same="identical"
      diff -r -q -x timing.json -x log.txt -x slurm "$WORK/local" "$WORK/slurm_$per_task" > /dev/null || same="DIFFERENT"
      echo "overhead: Slurm with $per_task job(s) per array task: median ratio Slurm / local" \
           "$(echo ${ratios[$per_task]} | tr ' ' '\n' | median) of${ratios[$per_task]} (target <= 1.15); outputs $same"
    done
    stop_local_slurm
  fi
else
  echo "overhead: not measured (no shared data at $SHARED_DATA)"
fi

if [ $SKIP_MC -eq 0 ]; then
  per_job=50
  [ "$FLIGHTS" -lt "$per_job" ] && per_job="$FLIGHTS"
  cat > "$WORK/mc.yaml" << EOF
campaign: {name: mc}
monte_carlo:
  - {study: ge, seed: 1, flights: $FLIGHTS, flights_per_job: $per_job, duration_min: 30, systems: GE}
EOF
  t0=$(now)
  "$CAMPAIGN" run "$WORK/mc.yaml" --out "$WORK/mc" --local --jobs 2 --no-plot > "$WORK/mc.log" 2>&1 \
    || { echo "bench_campaign: the Monte Carlo campaign failed:"; tail -5 "$WORK/mc.log"; }
  t1=$(now)
  mc_s=$(elapsed "$t0" "$t1")
  echo "monte carlo: $FLIGHTS flights of 30 min (GPS + Galileo) on 2 cores: $mc_s s" \
       "($(awk -v n="$FLIGHTS" -v s="$mc_s" 'BEGIN {printf "%.1f", n / (2 * s / 60)}') flights per core-minute; target: 1000 in < 600 s)"
  grep -o '"simulate_s": [0-9.e+-]*, "ekf_s": [0-9.e+-]*, "smoother_s": [0-9.e+-]*' "$WORK/mc/monte_carlo/ge/summary.json" \
    | sed 's/^/monte carlo: per-flight sums: /'
fi

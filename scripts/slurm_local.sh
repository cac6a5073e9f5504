# Sourced by scripts/test_campaign_slurm.sh and scripts/bench_campaign.sh: a private
# single-node Slurm cluster on this machine (Debian's slurm-wlm and munge), all of it
# under one directory: munged with its own key and socket, slurmctld and slurmd on
# free loopback ports, state, spool and logs there. No cgroups (proctrack/linuxproc,
# task/none), no accounting database (sacct then reports that accounting is off and
# the campaign reads the exit states from its job markers and squeue).
#
#   start_local_slurm DIR CPUS   -> 0 when `sinfo` shows the node idle; exports
#                                   SLURM_CONF; 2 when it cannot run here (not root,
#                                   programs missing: SLURM_SKIP_REASON says why);
#                                   1 when it did not come up (logs in DIR)
#   stop_local_slurm             -> stops what start_local_slurm started (by pid)

SLURM_LOCAL_PIDS=()

start_local_slurm() {
  local dir="$1" cpus="${2:-2}" p
  SLURM_SKIP_REASON=""
  for p in munged slurmctld slurmd sbatch squeue sinfo scancel; do
    if ! command -v "$p" > /dev/null 2>&1; then
      SLURM_SKIP_REASON="$p not installed (scripts/setup_deps.sh installs slurm-wlm and munge)"
      return 2
    fi
  done
  if [ "$(id -u)" -ne 0 ]; then
    SLURM_SKIP_REASON="not root: slurmd must run as root to start jobs as the submitting user"
    return 2
  fi
  mkdir -p "$dir"/{munge,state,spool,log}
  chmod 700 "$dir/munge"
  head -c 1024 /dev/urandom > "$dir/munge/munge.key"
  chmod 400 "$dir/munge/munge.key"
  munged --force --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munge.seed" \
    > "$dir/log/munged.out" 2>&1 || { echo "munged did not start (see $dir/log)" >&2; return 1; }
  SLURM_LOCAL_PIDS+=("$(cat "$dir/munge/munged.pid")")

  local ctld_port slurmd_port node="campaign$$"
  ctld_port="$(free_port)"
  slurmd_port="$(free_port)"
  cat > "$dir/slurm.conf" << EOF
ClusterName=pppcampaign
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
# run the scheduler on every submission and job end (default: at most every 2 s)
SchedulerParameters=sched_min_interval=20000,batch_sched_delay=0
MpiDefault=none
ReturnToService=2
MinJobAge=600
KillWait=5
NodeName=$node NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=2000 State=UNKNOWN
PartitionName=campaign Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/slurm.conf"
  setsid slurmctld -D -i -f "$SLURM_CONF" > "$dir/log/slurmctld.out" 2>&1 &
  SLURM_LOCAL_PIDS+=("$!")
  setsid slurmd -D -N "$node" -f "$SLURM_CONF" > "$dir/log/slurmd.out" 2>&1 &
  SLURM_LOCAL_PIDS+=("$!")
  local i state
  for i in $(seq 1 150); do
    state="$(sinfo -h -n "$node" -o '%t' 2>/dev/null | head -1)"
    [ "$state" = "idle" ] && return 0
    sleep 0.2
  done
  echo "slurm did not show node $node idle within 30 s (state '$state'; logs in $dir/log)" >&2
  return 1
}

stop_local_slurm() {
  local pid k i
  # slurmd, slurmctld, then munged (the reverse of the start order)
  for ((i = ${#SLURM_LOCAL_PIDS[@]} - 1; i >= 0; i--)); do
    pid="${SLURM_LOCAL_PIDS[$i]}"
    kill -TERM "$pid" 2>/dev/null || continue
    for k in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  SLURM_LOCAL_PIDS=()
}

#!/usr/bin/env bash
# A single-node Slurm cluster for tests, everything under one folder:
#   slurm_cluster.sh start DIR   munge key, slurm.conf (this node's real CPUs and memory from
#                                `slurmd -C`, no cgroups: proctrack/linuxproc, task/none), munged,
#                                slurmctld and slurmd as root in the background; waits until the
#                                node is idle. Clients use it with SLURM_CONF=DIR/slurm.conf.
#   slurm_cluster.sh stop DIR    cancels the cluster's jobs and stops the daemons it started.
# Needs root and the Debian 12 packages slurm-wlm and munge. Exits non-zero with the reason.
set -euo pipefail

usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
dir=$2
fail() { echo "slurm_cluster: $*" >&2; exit 1; }

# Waits up to $1 seconds for the command after it to succeed.
wait_for() {
  local seconds=$1; shift
  local end=$((SECONDS + seconds))
  until "$@" >/dev/null 2>&1; do
    [ $SECONDS -lt $end ] || return 1
    sleep 0.5
  done
}

stop_pid() {  # name: kill the daemon whose pid DIR/NAME.pid holds (started by this script), wait up to 10 s
  local file="$dir/$1.pid" pid
  [ -f "$file" ] || return 0
  pid=$(cat "$file")
  if kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 20); do kill -0 "$pid" 2>/dev/null || break; sleep 0.5; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}

case "$action" in
start)
  [ "$(id -u)" -eq 0 ] || fail "needs root (slurmctld and slurmd run as root here)"
  for b in munged slurmctld slurmd sbatch squeue sinfo; do
    command -v "$b" >/dev/null || fail "$b not found: apt-get install slurm-wlm munge"
  done
  mkdir -p "$dir"
  chmod 700 "$dir"
  dir=$(cd "$dir" && pwd)
  mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
  chmod 700 "$dir/munge"
  host=$(hostname -s)
  # Ports of this cluster only: two test runs on one machine (a developer's and CI's) do not meet.
  port=$((20000 + $$ % 20000))

  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge.pid" --log-file="$dir/munged.log" --seed-file="$dir/munge/munge.seed" \
    || fail "munged did not start: $(tail -3 "$dir/munged.log" 2>/dev/null)"

  node=$(slurmd -C | head -1 | sed "s/^NodeName=[^ ]*/NodeName=$host NodeAddr=127.0.0.1/")
  case "$node" in *RealMemory=*) ;; *) fail "slurmd -C gave no node line: $node" ;; esac
  cat > "$dir/slurm.conf" <<EOF
ClusterName=s4dtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
KillWait=30
MinJobAge=600
SchedulerParameters=sched_interval=2
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
$node State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/slurm.conf"
  echo "export SLURM_CONF=$dir/slurm.conf" > "$dir/env"
  slurmctld -i -f "$SLURM_CONF" || fail "slurmctld did not start: $(tail -5 "$dir/slurmctld.log" 2>/dev/null)"
  wait_for 30 scontrol ping || fail "slurmctld does not answer after 30 s: $(tail -5 "$dir/slurmctld.log" 2>/dev/null)"
  slurmd -f "$SLURM_CONF" -N "$host" || fail "slurmd did not start: $(tail -5 "$dir/slurmd.log" 2>/dev/null)"
  idle() { sinfo -h -N -o %t | grep -q '^idle'; }
  wait_for 60 idle || fail "the node is not idle after 60 s ($(sinfo -h -N -o '%t %E' 2>&1)): $(tail -5 "$dir/slurmd.log" 2>/dev/null)"
  echo "slurm_cluster: up ($node), SLURM_CONF=$SLURM_CONF" >&2
  ;;
stop)
  [ -d "$dir" ] || exit 0
  dir=$(cd "$dir" && pwd)
  if [ -f "$dir/slurm.conf" ]; then
    export SLURM_CONF="$dir/slurm.conf"
    timeout 10 scancel --quiet -u root >/dev/null 2>&1 || true  # every job of this cluster (root's: see start)
    no_jobs() { [ -z "$(timeout 5 squeue -h -o %i 2>/dev/null)" ]; }
    wait_for 15 no_jobs || echo "slurm_cluster: jobs still listed after scancel; stopping anyway" >&2
  fi
  stop_pid slurmd
  stop_pid slurmctld
  stop_pid munge
  echo "slurm_cluster: stopped ($dir)" >&2
  ;;
*) usage ;;
esac

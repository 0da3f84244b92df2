#!/usr/bin/env bash
# scripts/slurm-local.sh start|stop|status [DIR]
#
# A real single-node Slurm cluster on this machine, for tests and for trying `terralod build
# --scheduler slurm` (issue 25): Debian's munge and Slurm daemons (slurm-wlm, from
# scripts/install-deps.sh), run as the current user with everything under DIR (default
# ${TMPDIR:-/tmp}/terralod-slurm): a fresh munge key and socket, slurm.conf with absolute paths,
# state and spool directories, logs. No cgroups: processes are tracked by their parentage
# (proctrack/linuxproc) and tasks get no binding (task/none). The node has this machine's
# processors and memory, so jobs run as they would on one node of a cluster.
#
#   start   writes the configuration, starts munged, slurmctld and slurmd, waits (at most 60 s)
#           until the node is idle, and prints `export SLURM_CONF=DIR/slurm.conf`, which the
#           Slurm commands (sbatch, squeue, scancel, sinfo) need to find this cluster
#   stop    stops the daemons (SIGTERM, then SIGKILL) and removes DIR
#   status  sinfo's line for the node, or exit code 1 when the cluster is not running
#
# SLURM_LOCAL_CPUS=N gives the node N processors whatever the machine has (slurmd told to
# believe the configuration): the tests use 8, so that 8 small jobs start at once instead of
# in waves. Benchmarks leave it unset.
set -euo pipefail

action=${1:-}
dir=${2:-${TMPDIR:-/tmp}/terralod-slurm}
die() {
  echo "slurm-local: error: $*" >&2
  exit 1
}
case "$action" in start | stop | status) ;; *)
  sed -n '2p' "$0" | sed 's/^# //' >&2
  exit 2
  ;;
esac
if [ "$action" != start ] && [ ! -d "$dir" ]; then
  [ "$action" = stop ] && exit 0
  die "no cluster running in $dir"
fi
dir=$(mkdir -p "$dir" && cd "$dir" && pwd)
conf="$dir/slurm.conf"
export SLURM_CONF=$conf

# Only a directory this script made is ever cleared or removed.
ours() { [ -f "$conf" ] && head -n 1 "$conf" | grep -q '^# Written by scripts/slurm-local.sh'; }
if ! ours && [ -n "$(ls -A "$dir")" ]; then
  [ "$action" = status ] && die "no cluster running in $dir"
  die "$dir is not empty and is not a cluster this script started"
fi

pid_of() { [ -s "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null && cat "$1"; }

# SIGTERM to every daemon at once (each exits cleanly on it within about 2 s; `scontrol
# shutdown` takes longer), then SIGKILL to any still there after 5 s.
stop_all() {
  local pids=() pid
  for name in slurmd slurmctld munged; do
    pid=$(pid_of "$dir/$name.pid" || true)
    [ -z "$pid" ] || pids+=("$pid")
  done
  [ ${#pids[@]} -gt 0 ] || return 0
  # Jobs still running first: their processes would outlive slurmd.
  if pid_of "$dir/slurmctld.pid" >/dev/null; then
    timeout 5 scancel --quiet --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 50); do
      [ -z "$(timeout 5 squeue -h -o %i 2>/dev/null)" ] && break
      sleep 0.1
    done
  fi
  kill "${pids[@]}" 2>/dev/null || true
  for _ in $(seq 100); do
    kill -0 "${pids[@]}" 2>/dev/null || return 0  # (true while any is alive)
    sleep 0.05
  done
  kill -9 "${pids[@]}" 2>/dev/null || true
}

if [ "$action" = status ]; then
  [ -f "$conf" ] && pid_of "$dir/slurmctld.pid" >/dev/null || die "no cluster running in $dir"
  sinfo -h -o '%N %t %c CPUs %m MB'
  exit 0
fi
if [ "$action" = stop ]; then
  stop_all
  if ours; then rm -rf "$dir"; else rmdir "$dir" 2>/dev/null || true; fi
  exit 0
fi

for tool in munged slurmctld slurmd sinfo scontrol; do
  command -v "$tool" >/dev/null || [ -x "/usr/sbin/$tool" ] ||
    die "no $tool (run scripts/install-deps.sh: Debian's munge and slurm-wlm)"
done
export PATH="$PATH:/usr/sbin"
if pid_of "$dir/slurmctld.pid" >/dev/null; then die "a cluster is already running in $dir"; fi
stop_all
rm -rf "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
chmod 700 "$dir/munge"

# Free TCP ports for slurmctld and slurmd.
free_port() {
  node -e 'const s = require("net").createServer(); s.listen(0, "127.0.0.1", () => { console.log(s.address().port); s.close(); });' 2>/dev/null ||
    echo $((20000 + RANDOM % 20000))
}
ctld_port=$(free_port)
slurmd_port=$(free_port)
[ "$ctld_port" != "$slurmd_port" ] || slurmd_port=$((ctld_port + 1))

# munge: a fresh key (only this cluster's daemons and commands hold it) and its own socket.
head -c 1024 /dev/urandom >"$dir/munge/munge.key"
chmod 400 "$dir/munge/munge.key"
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munged.pid" --log-file="$dir/log/munged.log" \
  --seed-file="$dir/munge/munge.seed" ||
  die "munged did not start: $(tail -n 1 "$dir/log/munged.log" 2>/dev/null)"

cpus=${SLURM_LOCAL_CPUS:-$(nproc)}
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || die "SLURM_LOCAL_CPUS must be a whole number of processors"
overrides=
[ "$cpus" -le "$(nproc)" ] || overrides="SlurmdParameters=config_overrides"
memory=$(awk '/MemTotal/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
user=$(id -un)
# An epilog, even one that does nothing, makes slurmd report each job's end
# (MESSAGE_EPILOG_COMPLETE), on which slurmctld runs its scheduler at once. Without one the end
# is only noticed on slurmctld's once-a-second background pass, so each wave of queued array
# tasks waited up to a second (and dependent jobs as long).
epilog=$(type -P true)
cat >"$conf" <<CONF
# Written by scripts/slurm-local.sh: a single-node cluster under $dir.
ClusterName=terralod
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CryptoType=crypto/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
Epilog=$epilog
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
$overrides
NodeName=node1 NodeHostname=$(hostname -s) NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=main Nodes=node1 Default=YES MaxTime=INFINITE State=UP
CONF

slurmctld -f "$conf" -c || die "slurmctld did not start: $(tail -n 1 "$dir/log/slurmctld.log" 2>/dev/null)"
slurmd -f "$conf" -N node1 || die "slurmd did not start: $(tail -n 1 "$dir/log/slurmd.log" 2>/dev/null)"
for _ in $(seq 300); do
  state=$(sinfo -h -n node1 -o %t 2>/dev/null || true)
  [ "$state" = idle ] && { echo "export SLURM_CONF=$conf"; exit 0; }
  sleep 0.2
done
stop_all
die "the node did not become idle within 60 s (state '${state:-none}'; logs in $dir/log)"

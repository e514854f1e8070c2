#!/usr/bin/env bash
# A one-node SLURM cluster on this machine, for the tests (tests/it/slurm.rs):
#
#   tests/slurm/cluster.sh install        Debian's slurm-wlm and munge, if missing (root, apt-get)
#   tests/slurm/cluster.sh start DIR      munged, slurmctld and slurmd, everything in DIR
#   tests/slurm/cluster.sh stop DIR       stops the three daemons started in DIR
#
# After `start`, SLURM_CONF=DIR/slurm.conf points sbatch, squeue and scancel at the cluster.
# The configuration is generated here: one node (this machine, its cores and memory), one
# partition, no cgroups (proctrack/linuxproc, task/none), no accounting, root as the SLURM
# user, a munge daemon of its own with a fresh key and socket in DIR, ports chosen free.
set -euo pipefail

need() { command -v "$1" >/dev/null 2>&1 || [ -x "/usr/sbin/$1" ]; }

install() {
    if need sbatch && need slurmctld && need slurmd && need munged; then
        return 0
    fi
    [ "$(id -u)" = 0 ] || { echo "installing SLURM needs root" >&2; exit 3; }
    command -v apt-get >/dev/null || { echo "no apt-get to install SLURM with" >&2; exit 3; }
    export DEBIAN_FRONTEND=noninteractive
    local pkgs="slurm-wlm munge"
    if ! apt-get install -y -q --no-install-recommends $pkgs >/dev/null 2>&1; then
        apt-get update -q >/dev/null
        apt-get install -y -q --no-install-recommends $pkgs >/dev/null
    fi
}

# A TCP port nobody listens on (from /proc/net/tcp*).
free_port() {
    local p
    while :; do
        p=$(( 20000 + RANDOM % 20000 ))
        if ! grep -qi ":$(printf '%04X' "$p") " /proc/net/tcp /proc/net/tcp6 2>/dev/null; then
            echo "$p"
            return
        fi
    done
}

start() {
    local d=$1
    mkdir -p "$d/state" "$d/spool" "$d/log"
    d=$(cd "$d" && pwd)
    local host cpus mem p1 p2
    host=$(hostname -s)
    cpus=$(nproc)
    mem=$(awk '/MemTotal/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
    p1=$(free_port)
    p2=$(free_port)
    while [ "$p2" = "$p1" ]; do p2=$(free_port); done
    head -c 1024 /dev/urandom > "$d/munge.key"
    chmod 400 "$d/munge.key"
    /usr/sbin/munged --key-file="$d/munge.key" --socket="$d/munge.sock" \
        --pid-file="$d/munged.pid" --log-file="$d/log/munged.log" --seed-file="$d/munge.seed" --force
    cat > "$d/slurm.conf" <<CONF
ClusterName=trubaltest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$p1
SlurmdPort=$p2
AuthType=auth/munge
AuthInfo=socket=$d/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=500
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
KillWait=5
Waittime=0
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF=$d/slurm.conf
    /usr/sbin/slurmctld -f "$d/slurm.conf"
    /usr/sbin/slurmd -f "$d/slurm.conf"
    # Wait until the node is idle (at most 30 s).
    for _ in $(seq 60); do
        if sinfo -h -o %t 2>/dev/null | grep -q idle; then
            return 0
        fi
        sleep 0.5
    done
    echo "the node did not come up; logs in $d/log:" >&2
    tail -n 20 "$d"/log/*.log >&2 || true
    stop "$d"
    exit 1
}

stop() {
    local d=$1 f
    for f in slurmd slurmctld munged; do
        if [ -f "$d/$f.pid" ]; then
            kill "$(cat "$d/$f.pid")" 2>/dev/null || true
        fi
    done
}

case "${1:-}" in
    install) install ;;
    start) start "${2:?DIR}" ;;
    stop) stop "${2:?DIR}" ;;
    *) echo "usage: $0 install | start DIR | stop DIR" >&2; exit 2 ;;
esac

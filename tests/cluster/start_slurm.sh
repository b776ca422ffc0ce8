#!/usr/bin/env bash
# Start a single-node Slurm on this machine for the cluster tests
# (tests/workflow/test_slurm.py): Debian's slurm-wlm and munge, installed
# when missing (root only), one node with this machine's CPUs and memory, no
# accounting, slurmctld and slurmd started by hand (no systemd). Idempotent:
# exits 0 at once when the node already answers. On failure it prints one
# line saying why and exits non-zero.
set -uo pipefail

fail() { echo "start_slurm: $*"; exit 1; }

node_state() { sinfo -h -o %T 2>/dev/null | head -1; }

if command -v sinfo >/dev/null && [[ "$(node_state)" =~ ^(idle|mixed|allocated) ]]; then
    exit 0
fi
[[ $(id -u) -eq 0 ]] || fail "not root: cannot install or start Slurm"
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    command -v apt-get >/dev/null || fail "no apt-get: cannot install slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get install -y -q slurm-wlm munge >/tmp/start_slurm_apt.log 2>&1 \
        || { apt-get update -q >>/tmp/start_slurm_apt.log 2>&1 \
             && apt-get install -y -q slurm-wlm munge >>/tmp/start_slurm_apt.log 2>&1; } \
        || fail "apt-get install slurm-wlm munge failed (see /tmp/start_slurm_apt.log)"
fi

# munge: a key, then the daemon
if [[ ! -s /etc/munge/munge.key ]]; then
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
fi
chown munge:munge /etc/munge/munge.key && chmod 400 /etc/munge/munge.key
mkdir -p /run/munge /var/log/munge /var/lib/munge && chown munge:munge /run/munge /var/log/munge /var/lib/munge
pgrep -x munged >/dev/null || su -s /bin/sh munge -c /usr/sbin/munged || fail "munged did not start"

host=$(hostname -s)
cpus=$(nproc)
memory=$(( $(free -m | awk '/^Mem:/ {print $2}') - 1024 ))
spool=/var/spool/slurm-test
mkdir -p "$spool/ctld" "$spool/d" /var/log/slurm-test
cat >/etc/slurm/slurm.conf <<CONF
# Written by tests/cluster/start_slurm.sh: one node, no accounting.
ClusterName=test
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
StateSaveLocation=$spool/ctld
SlurmdSpoolDir=$spool/d
SlurmctldPidFile=/run/slurmctld-test.pid
SlurmdPidFile=/run/slurmd-test.pid
SlurmctldLogFile=/var/log/slurm-test/slurmctld.log
SlurmdLogFile=/var/log/slurm-test/slurmd.log
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
pgrep -x slurmctld >/dev/null || /usr/sbin/slurmctld || fail "slurmctld did not start (/var/log/slurm-test/slurmctld.log)"
pgrep -x slurmd >/dev/null || /usr/sbin/slurmd || fail "slurmd did not start (/var/log/slurm-test/slurmd.log)"
for _ in $(seq 60); do
    state=$(node_state)
    [[ "$state" =~ ^(idle|mixed|allocated) ]] && exit 0
    [[ "$state" =~ ^(down|drain) ]] && scontrol update NodeName="$host" State=RESUME >/dev/null 2>&1
    sleep 1
done
fail "the node did not become idle within 60 s (state: ${state:-none}; see /var/log/slurm-test/)"

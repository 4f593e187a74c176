#!/usr/bin/env bash
# A single-node Slurm on this machine, for trying `refract sweep plan
# --engine slurm` (README, "Scaling out") and for CI's test of it.
#
#   sudo bash scripts/local-slurm.sh install   # Debian: munge, slurmctld, slurmd, slurm-client
#   sudo bash scripts/local-slurm.sh start     # munge key, munged, slurm.conf, slurmctld, slurmd
#   sudo bash scripts/local-slurm.sh stop
#
# The cluster is this host alone (all its cores and 90 % of its memory),
# one partition `local`, no accounting, no cgroups (so it runs in a plain
# container as root). `start` returns when `sinfo` shows the node idle, or
# fails with the daemons' logs.
set -euo pipefail

conf_dir=/etc/slurm
state=/var/spool/slurm
logs=/var/log/slurm

install() {
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y --no-install-recommends munge slurmctld slurmd slurm-client ||
    { apt-get update && apt-get install -y --no-install-recommends munge slurmctld slurmd slurm-client; }
}

start() {
  host=$(hostname -s)
  cpus=$(nproc)
  # The daemons look the controller and node up by name: make sure this
  # host's name resolves (containers often lack it in /etc/hosts).
  if ! getent hosts "$host" >/dev/null 2>&1; then
    echo "127.0.0.1 $host" >>/etc/hosts
  fi
  mem_mb=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) * 9 / 10 / 1024 ))
  mkdir -p "$conf_dir" "$state/ctld" "$state/d" "$logs" /run/munge /var/lib/munge /var/log/munge
  # munge: a key, and the daemon (as root: a container has no munge user session).
  if [ ! -s /etc/munge/munge.key ]; then
    if command -v mungekey >/dev/null; then mungekey --create --force; else
      dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null; fi
  fi
  chown -R munge:munge /etc/munge /run/munge /var/lib/munge /var/log/munge 2>/dev/null || true
  chmod 0400 /etc/munge/munge.key
  if ! pgrep -x munged >/dev/null; then
    if id munge >/dev/null 2>&1; then
      su -s /bin/sh munge -c "munged" || munged --force
    else
      munged --force
    fi
  fi
  cat >"$conf_dir/slurm.conf" <<EOF
# Written by refract's scripts/local-slurm.sh: a one-node cluster.
ClusterName=refract-local
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/d
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=$logs/slurmctld.log
SlurmdLogFile=$logs/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=300
SlurmdTimeout=60
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  : >"$conf_dir/cgroup.conf"
  pgrep -x slurmctld >/dev/null || slurmctld
  pgrep -x slurmd >/dev/null || slurmd
  for _ in $(seq 1 60); do
    if sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
      echo "local-slurm: node $host up ($cpus CPUs, $mem_mb MB), partition local"
      return 0
    fi
    sleep 1
  done
  echo "local-slurm: the Slurm daemons did not come up in 60 s" >&2
  sinfo >&2 || true
  tail -n 20 "$logs/slurmctld.log" "$logs/slurmd.log" >&2 || true
  return 1
}

stop() {
  pkill -x slurmd || true
  pkill -x slurmctld || true
  pkill -x munged || true
}

case "${1:-}" in
  install) install ;;
  start) start ;;
  stop) stop ;;
  *) echo "usage: $0 install|start|stop" >&2; exit 2 ;;
esac

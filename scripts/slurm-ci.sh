#!/usr/bin/env bash
# The Monte Carlo's Slurm path on a real single-node Slurm: starts munge,
# slurmctld and slurmd on this machine with a minimal generated
# slurm.conf, submits the real array job and merge job through
# scripts/montecarlo-slurm.sh with sbatch, waits for both, and compares
# the merged samples.csv with a single run byte for byte.
#
# Needs root and Debian's slurm-wlm and munge (installed when missing).
# Where the daemons cannot start (no root, a sandbox without the needed
# privileges), it says why and runs the same shards through the script's
# LOCAL=1 mode instead; it never reports a Slurm pass it did not see.
#
#   scripts/slurm-ci.sh [SHARDS] [montecarlo options…]
#
# XTASK=path runs that xtask binary instead of `cargo xtask` (passed on to
# scripts/montecarlo-slurm.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

shards=${1:-3}
shift || true
args=("$@")
[[ ${#args[@]} -gt 0 ]] || args=(--experiment attitude --samples 30 --deadline 40)
experiment=position
for ((i = 0; i < ${#args[@]}; i++)); do
    [[ "${args[$i]}" == --experiment ]] && experiment=${args[$((i + 1))]}
done
out=target/montecarlo/$experiment
single=target/montecarlo/$experiment-single
work=$(mktemp -d /tmp/gpid-slurm.XXXXXX)

fallback() {
    echo "slurm: $1; falling back to LOCAL=1 (the same shard and merge commands, run here)"
    [[ -n "${2:-}" && -f "$2" ]] && tail -5 "$2" | sed 's/^/  | /'
    LOCAL=1 scripts/montecarlo-slurm.sh "$shards" "${args[@]}" >/dev/null
    compare "local mode"
    exit 0
}

compare() {
    if [[ -n "${XTASK:-}" ]]; then "$XTASK" montecarlo "${args[@]}" --out "$single" >/dev/null
    else cargo xtask montecarlo "${args[@]}" --out "$single" >/dev/null; fi
    cmp "$out/samples.csv" "$single/samples.csv"
    echo "slurm ($1): $shards shards merged = one run: cmp $out/samples.csv $single/samples.csv: identical ($(($(wc -l < "$single/samples.csv") - 1)) samples)"
}

if [[ $(id -u) != 0 ]]; then
    fallback "not root (the daemons need it)"
fi
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >"$work/apt.log" 2>&1 ||
        fallback "slurm-wlm and munge could not be installed" "$work/apt.log"
fi

# munge: a fresh key, the daemon as its own user.
mkdir -p /etc/munge /run/munge /var/lib/munge /var/log/munge
[[ -s /etc/munge/munge.key ]] || dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
chown -R munge:munge /etc/munge /run/munge /var/lib/munge /var/log/munge
chmod 0400 /etc/munge/munge.key
chmod 0755 /run/munge
if ! pgrep -x munged >/dev/null; then
    runuser -u munge -- /usr/sbin/munged >"$work/munged.log" 2>&1 ||
        fallback "munged did not start" "$work/munged.log"
fi
munge -n | unmunge >/dev/null 2>&1 || fallback "munge does not round-trip a credential"

# A one-node cluster named after this host.
node=$(hostname -s)
cpus=$(nproc)
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
cat > /etc/slurm/slurm.conf <<CONF
ClusterName=gpid-ci
SlurmctldHost=$node
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=$node CPUs=$cpus State=UNKNOWN
PartitionName=ci Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
# slurmd loads a cgroup plugin whatever the proctrack and task plugins
# are (22.05 has no "disabled"): the v1 hierarchy when it is mounted (as in
# this machine's containers), else v2; nothing is constrained.
if [[ -d /sys/fs/cgroup/freezer ]]; then cg=cgroup/v1; else cg=cgroup/v2; fi
printf 'CgroupPlugin=%s\nCgroupMountpoint=/sys/fs/cgroup\nConstrainCores=no\nConstrainRAMSpace=no\nConstrainDevices=no\n' "$cg" > /etc/slurm/cgroup.conf
pkill -x slurmctld 2>/dev/null || true
pkill -x slurmd 2>/dev/null || true
sleep 1
slurmctld -c >"$work/slurmctld.out" 2>&1 || fallback "slurmctld did not start" /var/log/slurm/slurmctld.log
slurmd >"$work/slurmd.out" 2>&1 || fallback "slurmd did not start" /var/log/slurm/slurmd.log
for _ in $(seq 30); do
    state=$(sinfo -h -n "$node" -o %t 2>/dev/null || true)
    [[ "$state" == idle* ]] && break
    sleep 1
done
[[ "$state" == idle* ]] || fallback "node $node is '${state:-unknown}', not idle, after 30 s" /var/log/slurm/slurmd.log
echo "slurm: $(sinfo --version), node $node idle with $cpus CPUs"

# The real submission: an array job of SHARDS tasks and the merge job
# that depends on it.
rm -rf "$out"
CPUS_PER_TASK=1 scripts/montecarlo-slurm.sh "$shards" "${args[@]}" | tee "$work/submit.log"
array=$(sed -n 's/^submitted array job \([0-9]*\).*/\1/p' "$work/submit.log")
merge=$(sed -n 's/.*merge job \([0-9]*\).*/\1/p' "$work/submit.log")
[[ -n "$array" && -n "$merge" ]] || { echo "slurm: no job ids in the submission's output"; exit 1; }
deadline=$((SECONDS + 900))
while squeue -h -j "$array,$merge" 2>/dev/null | grep -q .; do
    ((SECONDS < deadline)) || { echo "slurm: jobs $array and $merge still queued after 900 s"; squeue; exit 1; }
    sleep 2
done
for log in "$out"/slurm-*.log; do
    echo "  $(basename "$log"): $(tail -1 "$log")"
done
[[ -s "$out/samples.csv" ]] || { echo "slurm: the merge job $merge wrote no samples.csv"; cat "$out"/slurm-merge-*.log; exit 1; }
compare "array job $array, merge job $merge"
pkill -x slurmd || true
pkill -x slurmctld || true

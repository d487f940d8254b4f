#!/usr/bin/env bash
# Monte Carlo on a Slurm cluster: one array task per shard, then a merge
# job that starts when every shard has finished.
#
#   scripts/montecarlo-slurm.sh SHARDS [montecarlo options…]
#   e.g. scripts/montecarlo-slurm.sh 16 --experiment position --samples 100000 --seed 1
#
# Every shard writes target/montecarlo/<experiment>/shard-K-of-N/ (shared
# file system); the merge writes target/montecarlo/<experiment>/. The
# samples are keyed by (seed, index), so the merged files equal a
# single-machine run byte for byte in samples.csv.
#
# DRY_RUN=1 prints the commands instead of submitting them, and
# LOCAL=1 runs them here one after the other (the test of the shard and
# merge logic without Slurm). XTASK=path uses that xtask binary instead of
# building one.
set -euo pipefail
cd "$(dirname "$0")/.."

shards=${1:?usage: $0 SHARDS [montecarlo options…]}
shift
case "$shards" in ''|*[!0-9]*|0) echo "SHARDS must be a positive integer, got '$shards'" >&2; exit 2;; esac
experiment=position
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
    [[ "${args[$i]}" == --experiment ]] && experiment=${args[$((i + 1))]}
done
out=target/montecarlo/$experiment
cpus=${CPUS_PER_TASK:-2}

# Build once on the submitting node (the shared target directory), unless
# XTASK names an xtask binary already built (CI passes the one its
# workspace test build made).
if [[ -n "${XTASK:-}" ]]; then
    xtask=$XTASK
else
    cargo build -q -p xtask
    xtask=target/debug/xtask
fi

shard_cmd() { echo "$xtask montecarlo ${args[*]} --threads $cpus --shard $1/$shards --out $out/shard-$1-of-$shards"; }
merge_cmd() {
    local dirs=()
    for ((k = 0; k < shards; k++)); do dirs+=("$out/shard-$k-of-$shards"); done
    echo "$xtask montecarlo merge ${dirs[*]} --out $out"
}

if [[ "${LOCAL:-0}" == 1 ]]; then
    for ((k = 0; k < shards; k++)); do eval "$(shard_cmd "$k")"; done
    eval "$(merge_cmd)"
    exit 0
fi

array_script=$(mktemp)
cat > "$array_script" <<SLURM
#!/usr/bin/env bash
#SBATCH --job-name=gpid-mc
#SBATCH --array=0-$((shards - 1))
#SBATCH --cpus-per-task=$cpus
#SBATCH --output=$out/slurm-%A_%a.log
set -euo pipefail
k=\$SLURM_ARRAY_TASK_ID
$xtask montecarlo ${args[*]} --threads $cpus --shard \$k/$shards --out $out/shard-\$k-of-$shards
SLURM

if [[ "${DRY_RUN:-0}" == 1 ]]; then
    cat "$array_script"
    echo "# then, after every array task: $(merge_cmd)"
    rm -f "$array_script"
    exit 0
fi
mkdir -p "$out"
job=$(sbatch --parsable "$array_script")
merge=$(sbatch --parsable --dependency=afterok:"$job" --job-name=gpid-mc-merge --output="$out/slurm-merge-%j.log" --wrap "$(merge_cmd)")
rm -f "$array_script"
echo "submitted array job $job ($shards shards) and its merge job $merge"

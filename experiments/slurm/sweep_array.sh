#!/bin/bash
# exoid sweep as a Slurm job array: task K of N runs the cells with cell % N == K (exoid reads
# SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT), each into its own folder; a dependent job merges.
#
#   sbatch experiments/slurm/sweep_array.sh            # submits the array and the merge
#   EXOID=/path/to/exoid CONFIG=my.toml OUT=results/sweep sbatch experiments/slurm/sweep_array.sh
#
#SBATCH --job-name=exoid-sweep
#SBATCH --array=0-3
#SBATCH --cpus-per-task=2
#SBATCH --output=exoid-sweep-%A_%a.out
set -euo pipefail
EXOID=${EXOID:-build/experiments/exoid}
CONFIG=${CONFIG:-experiments/configs/default_sweep.toml}
OUT=${OUT:-results/sweep}

# Re-running a task resumes it (finished runs are kept in $OUT/shard-K/runs/).
"$EXOID" sweep --config "$CONFIG" --out "$OUT/shard-$SLURM_ARRAY_TASK_ID" \
  --threads "${SLURM_CPUS_PER_TASK:-0}" --no-plots

# The first task submits the merge, to run once every task of the array has succeeded.
if [[ "$SLURM_ARRAY_TASK_ID" == "${SLURM_ARRAY_TASK_MIN:-0}" ]]; then
  shards=()
  for ((k = 0; k < SLURM_ARRAY_TASK_COUNT; ++k)); do shards+=("$OUT/shard-$k"); done
  sbatch --dependency="afterok:$SLURM_ARRAY_JOB_ID" --job-name=exoid-merge --output="exoid-merge-%j.out" \
    --wrap="$EXOID merge --out $OUT/merged ${shards[*]}"
fi

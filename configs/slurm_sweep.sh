#!/bin/bash
# A surfreg sweep as a Slurm job array: task K of N runs the K-th slice of the
# grid (--shard K/N) into its own CSV; a job that waits for the whole array
# merges the slices and writes the ranking and plots. Run from the project
# root on a shared file system (the config's paths are relative to it):
#
#   mkdir -p out
#   jid=$(sbatch --parsable --array=1-8 configs/slurm_sweep.sh configs/sweep_example.yaml out/sweep_example.csv)
#   sbatch --dependency=afterok:$jid --wrap \
#     "build/tools/surfreg merge out/sweep_example.csv out/sweep_example.shard*.csv &&
#      build/tools/surfreg sweep --config configs/sweep_example.yaml --resume"
#
# The last step runs nothing (every row is in the merged CSV) and writes
# out/sweep_example_summary.md and the PNG plots. A task that was preempted
# or timed out continues where it stopped when requeued (--resume keeps the
# rows streamed to its .partial file). Set SURFREG to use another binary.
#SBATCH --job-name=surfreg-sweep
#SBATCH --array=1-8
#SBATCH --cpus-per-task=4
#SBATCH --mem-per-cpu=1G
#SBATCH --time=02:00:00
#SBATCH --requeue
#SBATCH --output=out/slurm-sweep-%A_%a.log
set -euo pipefail
config=${1:?usage: sbatch --array=1-N slurm_sweep.sh SWEEP.yaml OUT.csv}
csv=${2:?usage: sbatch --array=1-N slurm_sweep.sh SWEEP.yaml OUT.csv}
surfreg=${SURFREG:-build/tools/surfreg}
k=$SLURM_ARRAY_TASK_ID
n=$SLURM_ARRAY_TASK_COUNT
"$surfreg" sweep --config "$config" --shard "$k/$n" --jobs "${SLURM_CPUS_PER_TASK:-1}" \
  --output "${csv%.csv}.shard$k.csv" --resume

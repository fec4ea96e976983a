#!/bin/bash
# A tiled measure of two large DEMs as a Slurm job array: task K of N measures
# the K-th band of tile rows (--shard K/N) into its own partial result and
# DoD band; a job that waits for the whole array merges them into the
# measure's report (OUT.json) and one DoD GeoTIFF, the same as one run's.
# Run from a directory on a shared file system:
#
#   mkdir -p out
#   jid=$(sbatch --parsable --array=1-8 configs/slurm_measure_tiled.sh A.tif B.tif out/ab)
#   sbatch --dependency=afterok:$jid --wrap \
#     "build/tools/surfreg merge out/ab.json out/ab.part*.json --dod=out/ab_dod.tif"
#
# The shards must use the same inputs, tile and settings (the merge checks).
# A task that was preempted or timed out continues from its last finished
# tile row when requeued (--resume; its state is in out/ab.partK.json.resume/).
# TILE is the tile side in cells (or set MAX_MEMORY, e.g. 2G, instead);
# SURFREG another binary.
#SBATCH --job-name=surfreg-measure
#SBATCH --array=1-8
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=02:00:00
#SBATCH --requeue
#SBATCH --output=out/slurm-measure-%A_%a.log
set -euo pipefail
usage="usage: sbatch --array=1-N slurm_measure_tiled.sh A.tif B.tif OUT_PREFIX"
a=${1:?$usage}
b=${2:?$usage}
out=${3:?$usage}
surfreg=${SURFREG:-build/tools/surfreg}
k=$SLURM_ARRAY_TASK_ID
n=$SLURM_ARRAY_TASK_COUNT
size=--tile=${TILE:-512}
[[ -n ${MAX_MEMORY:-} ]] && size=--max_memory=$MAX_MEMORY
"$surfreg" measure "$a" "$b" "$size" --shard "$k/$n" --partial "$out.part$k.json" \
  --dod "$out.dod$k.tif" --resume

#!/bin/bash
# A tiled measure of two large DEMs in N shards run by GNU parallel (here on
# this machine; add -S node1,node2 --wd . for other machines on a shared
# file system), then merged into the measure's report (OUT.json, and the
# text report on stdout) and one DoD GeoTIFF, the same as one run's:
#
#   configs/parallel_measure_tiled.sh A.tif B.tif out/ab 4
#
# Each shard is one process on two threads; --resume lets a rerun continue
# shards that were killed. Set TILE (cells, default 512) and SURFREG.
set -euo pipefail
a=${1:?usage: parallel_measure_tiled.sh A.tif B.tif OUT_PREFIX N}
b=${2:?} out=${3:?} n=${4:?}
surfreg=${SURFREG:-build/tools/surfreg}
parallel --will-cite -j "$(( $(nproc) / 2 > 0 ? $(nproc) / 2 : 1 ))" \
  "$surfreg" measure "$a" "$b" --tile="${TILE:-512}" --shard={}/"$n" --partial="$out".part{}.json \
  --dod="$out".dod{}.tif --resume --quiet ::: $(seq 1 "$n")
"$surfreg" merge "$out.json" "$out".part*.json --dod="$out"_dod.tif

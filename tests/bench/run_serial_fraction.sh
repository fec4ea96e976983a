#!/usr/bin/env bash
# The serial fraction of whole runs, and what it allows on more cores.
#
#   tests/bench/run_serial_fraction.sh [build_dir] [runs]
#
# Builds (if needed) and runs, each once with --threads=1 under
# SURFREG_REGION_TIMING=1 (the program then prints the time spent inside its
# parallel regions: docs/speed.md, Threads), and `runs` times (default 3)
# with --threads=1 and --threads=2 for the speed-up measured on this machine:
#   measure of two 1e6-point clouds (.xyz, uniform random),
#   align of two 2e5-point clouds (B turned by 0.8 degrees and shifted),
#   measure --dod of two 2000 x 2000 Float32 rasters on one grid and with B
#   offset by (0.37, -0.61) cells, and align of the offset pair (a minute
#   on one thread).
# Prints a Markdown table: the serial share of the one-thread run, the
# Amdahl projection on 2, 8, 16 and 64 cores (each region over min(cores,
# its chunks), never below its longest chunk), and the measured 2-thread
# speed-up (median wall times). Inputs are made in a temporary folder.
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source_dir=$(cd "$script_dir/../.." && pwd)
build_dir=${1:-$source_dir/build}
runs=${2:-3}
mkdir -p "$build_dir"
build_dir=$(cd "$build_dir" && pwd)
if [[ ! -f $build_dir/CMakeCache.txt ]]; then
  cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build_dir" -j2 --target surfreg >/dev/null
surfreg=$build_dir/tools/surfreg
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python=/usr/bin/python3  # Debian's, with numpy and GDAL's bindings

"$python" - "$tmp" <<'EOF'
import sys
import numpy as np
from osgeo import gdal, osr
out = sys.argv[1]
def cloud(name, n, seed, turn_deg=0.0, shift=(0.0, 0.0, 0.0), side=1000.0):
    rng = np.random.default_rng(seed)
    x, y = rng.uniform(0, side, n), rng.uniform(0, side, n)
    z = 20 * np.sin(x / 150.0) * np.cos(y / 130.0) + 0.02 * x + 5 * np.sin(x / 37.0 + y / 53.0)
    p = np.c_[x, y, z]
    if turn_deg:
        a, c = np.radians(turn_deg), p.mean(0)
        r = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
        p = (p - c) @ r.T + c + np.array(shift)
    np.savetxt(f"{out}/{name}.xyz", p, fmt="%.4f")
cloud("m_a", 1000000, 1)
cloud("m_b", 1000000, 2)
cloud("al_a", 200000, 3)
cloud("al_b", 200000, 4, 0.8, (3.0, -2.0, 0.5))
n = 2000
def raster(name, x0, y0, seed):
    rng = np.random.default_rng(seed)
    r, c = np.arange(n)[:, None], np.arange(n)[None, :]
    lx, ly = x0 + (c + 0.5) * 10 - 500000, y0 - (r + 0.5) * 10 - 4000000
    z = 300 + 40 * np.sin(lx / 370.0) * np.cos(ly / 230.0) + 0.01 * lx + rng.normal(0, 0.3, (n, n))
    d = gdal.GetDriverByName("GTiff").Create(f"{out}/{name}.tif", n, n, 1, gdal.GDT_Float32)
    d.SetGeoTransform((x0, 10, 0, y0, 0, -10))
    s = osr.SpatialReference()
    s.ImportFromEPSG(32633)
    d.SetProjection(s.ExportToWkt())
    d.GetRasterBand(1).WriteArray(z.astype(np.float32))
raster("r_a", 500000, 4000000, 5)
raster("r_b", 500000, 4000000, 6)
raster("r_c", 500000 + 3.7, 4000000 - 6.1, 7)
EOF

cd "$tmp"
median_wall() {  # median wall seconds of `runs` runs of the arguments
  local walls=()
  for _ in $(seq "$runs"); do
    /usr/bin/time -f "%e" -o "$tmp/time" "$@" >/dev/null 2>&1
    walls+=("$(cat "$tmp/time")")
  done
  printf '%s\n' "${walls[@]}" | sort -g | sed -n "$(((runs + 1) / 2))p"
}

cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
echo "CPU: $cpu, $(nproc) cores; $runs runs each"
echo
echo "| run | serial share (1 thread) | projected on 2 / 8 / 16 / 64 cores | measured, 2 threads against 1 |"
echo "|---|---:|---:|---:|"
row() {
  local label=$1
  shift
  local line
  line=$(SURFREG_REGION_TIMING=1 "$surfreg" "$@" --threads=1 2>&1 >/dev/null | grep "region timing" | tail -1)
  local share projected
  share=$(sed -E 's/.*\(([0-9.]+%)\).*/\1/' <<<"$line")
  projected=$(sed -E 's/.*cores: ([0-9.]+), ([0-9.]+), ([0-9.]+), ([0-9.]+)$/\1 \/ \2 \/ \3 \/ \4/' <<<"$line")
  local one two
  one=$(median_wall "$surfreg" "$@" --threads=1)
  two=$(median_wall "$surfreg" "$@" --threads=2)
  echo "| $label | $share | $projected | $(awk -v a="$one" -v b="$two" 'BEGIN { printf "%.2f (%.2f s, %.2f s)", a / b, a, b }') |"
}
row "measure, 1e6 + 1e6 points" measure m_a.xyz m_b.xyz --json
row "align, 2e5 + 2e5 points" align al_a.xyz al_b.xyz --json
row "measure --dod, 2000², one grid" measure r_a.tif r_b.tif --dod=d.tif --json
row "measure --dod, 2000², offset grid" measure r_a.tif r_c.tif --dod=d.tif --json
row "align, 2000² rasters, offset grid" align r_a.tif r_c.tif --json

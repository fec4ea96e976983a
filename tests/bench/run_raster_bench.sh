#!/usr/bin/env bash
# Rasters against GDAL's raster tools (issue 47): two N x N Float32 DEMs
# (10 m cells, UTM 33N, a round nodata hole, 0.3 m noise, a 3 m sink in B),
# on the same grid and with B's grid offset by (0.37, -0.61) cells. Times the
# whole process (GNU time: wall seconds, peak RSS) of
#   surfreg measure A B --dod=D           against  gdal_calc.py B - A
#   surfreg measure A B --max_memory=200M (tiled, no DoD)
#   surfreg measure A C --dod=D (offset)  against  gdalwarp -r bilinear C onto A's grid, then gdal_calc
# each the median of RUNS runs, and prints a Markdown table of the ratios.
#
#   bash tests/bench/run_raster_bench.sh [SURFREG] [N] [RUNS]
#   default: build/tools/surfreg, 2000, 3
set -euo pipefail
bin=$(realpath -- "${1:-build/tools/surfreg}")
n=${2:-2000}
runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python=/usr/bin/python3  # Debian's, with numpy and GDAL's bindings

"$python" - "$tmp" "$n" <<'EOF'
import sys
import numpy as np
from osgeo import gdal, osr
out, n = sys.argv[1], int(sys.argv[2])
def write(name, x0, y0, sink, seed):
    rng = np.random.default_rng(seed)
    r = np.arange(n)[:, None]
    c = np.arange(n)[None, :]
    lx, ly = x0 + (c + 0.5) * 10 - 500000, y0 - (r + 0.5) * 10 - 4000000
    z = 300 + 40 * np.sin(lx / 370.0) * np.cos(ly / 230.0) + 0.01 * lx + rng.normal(0, 0.3, (n, n))
    z -= sink * np.exp(-((lx - 5 * n) ** 2 + (ly + 5 * n) ** 2) / (2.0 * n * n))
    z[(lx - 3 * n) ** 2 + (ly + 3 * n) ** 2 < (0.5 * n) ** 2] = -9999
    d = gdal.GetDriverByName("GTiff").Create(f"{out}/{name}.tif", n, n, 1, gdal.GDT_Float32)
    d.SetGeoTransform((x0, 10, 0, y0, 0, -10))
    s = osr.SpatialReference()
    s.ImportFromEPSG(32633)
    d.SetProjection(s.ExportToWkt())
    b = d.GetRasterBand(1)
    b.SetNoDataValue(-9999)
    b.WriteArray(z.astype(np.float32))
write("a", 500000, 4000000, 0, 1)
write("b", 500000, 4000000, 3, 2)
write("c", 500000 + 3.7, 4000000 - 6.1, 3, 3)
EOF

# Median wall seconds and peak MiB of `runs` runs of a command (sh -c).
median_run() {
  local walls=() rsss=()
  for _ in $(seq "$runs"); do
    /usr/bin/time -f "%e %M" -o "$tmp/time" sh -c "$1" >/dev/null 2>&1
    read -r wall rss <"$tmp/time"
    walls+=("$wall")
    rsss+=("$rss")
  done
  printf '%s\n' "${walls[@]}" | sort -g | sed -n "$(((runs + 1) / 2))p"
  printf '%s\n' "${rsss[@]}" | sort -g | sed -n "$(((runs + 1) / 2))p"
}
cd "$tmp"
calc="gdal_calc.py -A a.tif -B b.tif --calc=B-A --outfile=g.tif --overwrite --quiet --NoDataValue=-9999"
warp="gdalwarp -q -overwrite -r bilinear -te 500000 3980000 520000 4000000 -tr 10 10 c.tif w.tif && \
gdal_calc.py -A a.tif -B w.tif --calc=B-A --outfile=g.tif --overwrite --quiet --NoDataValue=-9999"
[[ $n -eq 2000 ]] || warp=${warp//520000 4000000/$((500000 + 10 * n)) 4000000}
[[ $n -eq 2000 ]] || warp=${warp//3980000/$((4000000 - 10 * n))}
mapfile -t same < <(median_run "$bin measure a.tif b.tif --dod=d.tif --quiet")
mapfile -t tiled < <(median_run "$bin measure a.tif b.tif --max_memory=200M --quiet")
mapfile -t gcalc < <(median_run "$calc")
mapfile -t offset < <(median_run "$bin measure a.tif c.tif --dod=d.tif --quiet")
mapfile -t gwarp < <(median_run "$warp")

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores; $n x $n cells, median of $runs"
echo
echo "| run | wall (s) | peak (MiB) | peer | wall ratio | memory ratio |"
echo "|---|---:|---:|---|---:|---:|"
row() {  # name, surfreg's (wall, KiB), peer name, peer's (wall, KiB)
  awk -v name="$1" -v w="$2" -v m="$3" -v peer="$4" -v pw="$5" -v pm="$6" \
    'BEGIN { printf "| %s | %.2f | %.0f | %s | %.2f | %.2f |\n", name, w, m / 1024, peer, w / pw, m / pm }'
}
row "same grid, --dod" "${same[0]}" "${same[1]}" "gdal_calc B - A" "${gcalc[0]}" "${gcalc[1]}"
row "same grid, tiled (--max_memory=200M)" "${tiled[0]}" "${tiled[1]}" "gdal_calc B - A" "${gcalc[0]}" "${gcalc[1]}"
row "offset grid, --dod" "${offset[0]}" "${offset[1]}" "gdalwarp + gdal_calc" "${gwarp[0]}" "${gwarp[1]}"

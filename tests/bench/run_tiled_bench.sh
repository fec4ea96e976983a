#!/usr/bin/env bash
# Tiled measure at scale (issue 24): two synthetic DEMs of N x N cells (N up
# to 8000: 6.4e7 cells each), B on a grid shifted by a fraction of a cell,
# with nodata holes and a known change, measured with
# `surfreg measure --max_memory=BUDGET`; prints, per N, the wall time, the
# time per cell of A and the peak RSS (GNU time), as a Markdown table.
#
#   bash tests/bench/run_tiled_bench.sh [SURFREG] [BUDGET] [N ...]
#   default: build/tools/surfreg, 1G, 1000 2000 4000 8000
#
# The DEMs are ESRI .bil rasters (float32, written by numpy, read by GDAL's
# EHdr driver) in a scratch directory under /tmp (about 2 x 256 MB at 8000).
set -euo pipefail
bin=$(realpath -- "${1:-build/tools/surfreg}")
budget=${2:-1G}
shift $(($# > 2 ? 2 : $#))
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(1000 2000 4000 8000)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python=/usr/bin/python3  # Debian's, with numpy

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores; budget $budget"
echo
echo "| N x N cells | tiles | wall (s) | per cell of A (µs) | peak RSS (MiB) | ρd (m³) | cut (m³) |"
echo "|---:|---:|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  "$python" - "$tmp" "$n" <<'EOF'
import sys
import numpy as np
tmp, n = sys.argv[1], int(sys.argv[2])
def write(name, x0, y0, cell, bump, holes):
    # Row by row blocks: the 8000 x 8000 rasters never exist whole as float64.
    with open(f"{tmp}/{name}.bil", "wb") as f:
        for r0 in range(0, n, 500):
            rows = np.arange(r0, min(n, r0 + 500))
            y = y0 - (rows[:, None] + 0.5) * cell
            x = x0 + (np.arange(n)[None, :] + 0.5) * cell
            lx, ly = x - 1000.0, y - 5000.0
            z = 20 * np.sin(lx / 37) * np.cos(ly / 23) + 0.002 * lx
            z = z - bump * np.exp(-((lx - n / 2) ** 2 + (ly + n / 2) ** 2) / (0.02 * n * n))
            for hx, hy, hr in holes:
                z = np.where((lx - hx) ** 2 + (ly - hy) ** 2 < hr * hr, -9999.0, z)
            f.write(z.astype("<f4").tobytes())
    with open(f"{tmp}/{name}.hdr", "w") as f:
        f.write(f"BYTEORDER I\nLAYOUT BIL\nNROWS {n}\nNCOLS {n}\nNBANDS 1\nNBITS 32\n"
                f"PIXELTYPE FLOAT\nULXMAP {x0 + 0.5 * cell}\nULYMAP {y0 - 0.5 * cell}\n"
                f"XDIM {cell}\nYDIM {cell}\nNODATA -9999\n")
holes = [(0.3 * n, -0.3 * n, 0.05 * n), (0.7 * n, -0.6 * n, 20.0)]
write("a", 1000.0, 5000.0, 1.0, 0.0, holes)
write("b", 1000.37, 5000.61, 1.0, 2.0, [(0.5 * n, -0.8 * n, 0.03 * n)])
EOF
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$bin" measure "$tmp/a.bil" "$tmp/b.bil" --json --quiet \
    --max_memory="$budget" >"$tmp/out.json"
  read -r wall rss <"$tmp/time"
  "$python" - "$tmp/out.json" "$n" "$wall" "$rss" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
n, wall, rss = int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
print("| %d x %d | %d | %.1f | %.2f | %.0f | %.6g | %.6g |" % (
    n, n, j["tiles"], wall, 1e6 * wall / (n * n), rss / 1024, j["rho_d"], j["change"]["cut"]))
EOF
done

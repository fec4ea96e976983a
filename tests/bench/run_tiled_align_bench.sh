#!/usr/bin/env bash
# Tiled alignment at scale (issue 24): two synthetic DEMs of N x N cells (N
# up to 8000: 6.4e7 cells each), B the same terrain moved by a known rigid
# motion (hundredths of a degree about the centre, a few cells) on its own
# grid, both with nodata holes (tests/make_moved_pair.py), aligned with
# `surfreg align --max_memory=BUDGET`: the motion solved on patches, the
# whole pair measured after it tile by tile. Prints, per N, the wall time,
# the time per cell of A, the peak RSS (GNU time) and the errors against the
# known motion, as a Markdown table.
#
#   bash tests/bench/run_tiled_align_bench.sh [SURFREG] [BUDGET] [N ...]
#   default: build/tools/surfreg, 2G, 1000 2000 4000 8000
#
# The DEMs are ESRI .bil rasters (float32, numpy) in a scratch directory
# under /tmp (about 2 x 256 MB at 8000); making the 8000 pair takes minutes.
set -euo pipefail
here=$(dirname -- "$(realpath -- "$0")")
bin=$(realpath -- "${1:-build/tools/surfreg}")
budget=${2:-2G}
shift $(($# > 2 ? 2 : $#))
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(1000 2000 4000 8000)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python=/usr/bin/python3  # Debian's, with numpy

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores; budget $budget"
echo
echo "| N x N cells | samples solved on (A / B) | tiles | wall (s) | per cell of A (µs) | peak RSS (MiB) | rotation error (°) | translation error (cells) |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  "$python" "$here/../make_moved_pair.py" "$tmp" "$n"
  known=$(tr ' ' ',' <"$tmp/known.txt")
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$bin" align "$tmp/a.bil" "$tmp/b.bil" --quiet \
    --max_memory="$budget" --known_matrix="$known" --output="$tmp/out.json" >/dev/null
  read -r wall rss <"$tmp/time"
  "$python" - "$tmp/out.json" "$n" "$wall" "$rss" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["tiled"]
n, wall, rss = int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
s, k = t["sample"], t["known"]
print("| %d x %d | %d / %d | %d | %.1f | %.2f | %.0f | %.2g | %.2g |" % (
    n, n, s["reference_samples"], s["moving_samples"], t["tiles"], wall, 1e6 * wall / (n * n),
    rss / 1024, k["rotation_error_deg"], k["translation_error_cells"]))
PY
done

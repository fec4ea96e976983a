#!/usr/bin/env bash
# `surfreg align --max_memory=SIZE` (issue 24): two DEMs with a known rigid
# motion and nodata holes (make_moved_pair.py), aligned on a sample of
# patches within the budget, recover the motion (1e-4 degrees, 1e-3 cells);
# the whole pair is then measured tile by tile (DoD, per-tile dz statistics
# that add up to the whole); a budget the pair fits is solved on the whole
# pair; what a tiled alignment does not take is refused with one line.
# Usage: cli_tiled_align_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
here=$(dirname -- "$(realpath -- "$0")")
source "$here/cli_harness.sh"  # fail, run, expect_refused
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 2
failures=0
checks=0

# 400 x 400 cells (1.6e5): 340M holds four patches of 128 x 128, 2G the whole pair.
python3 "$here/make_moved_pair.py" . 400 || exit 2
known=$(tr ' ' ',' <known.txt)

run align a.bil b.bil --max_memory=340M --known_matrix="$known" --output=t.json --dod=dod.tif \
  --tile_stats=tiles.csv --matrix_txt=m.txt --patch_shifts=shifts.csv
[[ $rc -eq 0 ]] || fail "tiled align: exit $rc"
checks=$((checks + 1))
python3 - t.json tiles.csv shifts.csv <<'PY' || fail "tiled align: the motion, the sample, the tiles or the patch shifts"
import csv, json, sys
j = json.load(open(sys.argv[1]))
t = j["tiled"]
s, k = t["sample"], t["known"]
assert j["verdict"] == "converged_improved", j["verdict"]
assert s["whole"] is False and s["patches"] == 4 and s["patch"] == 128, s
assert s["reference_samples"] <= 4 * 128 * 128 < 400 * 400, s
assert k["rotation_error_deg"] < 1e-4 and k["translation_error_cells"] < 1e-3, k
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == t["tiles"] >= 1, (len(rows), t["tiles"])
assert sum(int(r["samples"]) for r in rows) == t["after"]["dz_count"] > 0.9 * 400 * 400
assert all(abs(float(r["dz_median"])) < 0.01 for r in rows if int(r["samples"]) > 0), rows
assert t["after"]["dz_rmse"] < 0.01 and abs(t["after"]["net"]) < 1e-3 * t["after"]["overlap_area"], t["after"]
# A rigid motion: every patch alone finds the whole motion (no shift beyond 1e-3 cells).
shifts = list(csv.DictReader(open(sys.argv[3])))
assert len(shifts) == s["patches"] == s["patch_shifts"], (len(shifts), s)
for r in shifts:
    assert r["verdict"].startswith("converged") and int(r["reference_samples"]) > 0.5 * 128 * 128, r
    assert max(abs(float(r[k])) for k in ("dx", "dy", "dz")) < 1e-3, r
    assert 0 < float(r["sigma_dx"]) < 1e-3, r
print("  tiled: %d patches, rotation error %.2g deg, translation %.2g cells, %d tiles" % (
    s["patches"], k["rotation_error_deg"], k["translation_error_cells"], t["tiles"]))
PY
[[ -s dod.tif && -s m.txt ]] || fail "tiled align: no DoD or matrix written"

run align a.bil b.bil --max_memory=2G --known_matrix="$known" --json --quiet
[[ $rc -eq 0 ]] || fail "tiled align with a budget the pair fits: exit $rc"
checks=$((checks + 1))
python3 -c '
import json, sys
t = json.load(sys.stdin)["tiled"]
assert t["sample"]["whole"] is True and t["sample"]["reference_samples"] > 0.9 * 400 * 400, t["sample"]
assert t["known"]["rotation_error_deg"] < 1e-4 and t["known"]["translation_error_cells"] < 1e-3, t["known"]
' <"$tmp/stdout" || fail "tiled align, whole pair: sample or motion"

# The least budget: one patch, several tiles whose statistics add up.
run align a.bil b.bil --max_memory=128M --known_matrix="$known" --output=small.json --tile_stats=small.csv \
  --sigma_reference=0.01 --sigma_moving=0.02 --lod_confidence=0.95
[[ $rc -eq 0 ]] || fail "tiled align at 128M: exit $rc"
checks=$((checks + 1))
python3 - small.json small.csv <<'PY' || fail "tiled align at 128M: the tiles"
import csv, json, sys
t = json.load(open(sys.argv[1]))["tiled"]
rows = list(csv.DictReader(open(sys.argv[2])))
assert t["sample"]["patches"] == 1 and t["tiles"] == len(rows) > 1, (t["sample"], t["tiles"], len(rows))
assert sum(int(r["samples"]) for r in rows) == t["after"]["dz_count"] > 0.9 * 400 * 400
assert t["known"]["rotation_error_deg"] < 1e-3 and t["known"]["translation_error_cells"] < 1e-2, t["known"]
u = t["after"]["uncertainty"]  # the change budget: no node beyond 1.96 sigma_DoD after a good alignment
assert u["nodes"] == t["after"]["dz_count"] and abs(u["sigma_dod_median"] - 0.05 ** 0.5 / 10) < 1e-12, u
assert u["fill_nodes"] + u["cut_nodes"] < 1e-3 * u["nodes"], u
PY

# A stretch along x (B = A moved, then stretched by 0.2%): the patches' own
# shifts map it, dx falling with x at the stretch's rate (moving -> reference).
mkdir -p stretched
python3 "$here/make_moved_pair.py" stretched 400 0.002 || exit 2
run align stretched/a.bil stretched/b.bil --max_memory=340M --patch_shifts=stretched.csv --quiet
[[ $rc -eq 0 ]] || fail "tiled align of a stretched pair: exit $rc"
checks=$((checks + 1))
python3 - stretched.csv <<'PY' || fail "patch shifts: the stretch is not mapped"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["verdict"].startswith("converged")]
assert len(rows) == 4, rows
x = [float(r["x"]) for r in rows]
dx = [float(r["dx"]) for r in rows]
mx, md = sum(x) / len(x), sum(dx) / len(dx)
slope = sum((a - mx) * (b - md) for a, b in zip(x, dx)) / sum((a - mx) ** 2 for a in x)
residual = max(abs(b - md - slope * (a - mx)) for a, b in zip(x, dx))
assert abs(slope + 0.002) < 0.0004 and residual < 0.05, (slope, residual, dx)
print("  patch shifts of a 0.2%% stretch: dx slope %.5f per cell" % slope)
PY

# The map of the DoD from its overview (a figure of a DoD never held whole).
if has_part plots; then
  run align a.bil b.bil --max_memory=128M --dod_png=map.png --lod=0.01 --quiet
  checks=$((checks + 1))
  [[ $rc -eq 0 && $(head -c 4 map.png | tail -c 3) == PNG ]] || fail "tiled align --dod_png: no PNG"
fi

# Two lon/lat DEMs: aligned in the untiled run's metric frame (UTM); a
# budget they fit gives the untiled motion.
mkdir -p lonlat
(cd lonlat && python3 "$here/make_tiled_pair.py" 0.2) || exit 2
run align lonlat/lla.asc lonlat/llb.asc --json --quiet
cp stdout lonlat_untiled.json
run align lonlat/lla.asc lonlat/llb.asc --json --quiet --max_memory=1G
checks=$((checks + 1))
python3 - lonlat_untiled.json stdout <<'PY' || fail "lon/lat DEMs: the tiled alignment differs from the untiled one"
import json, sys
u, t = (json.load(open(p)) for p in sys.argv[1:3])
assert t["tiled"]["sample"]["whole"] is True and u["verdict"] == t["verdict"] == "converged_improved"
assert max(abs(a - b) for ru, rt in zip(u["matrix"], t["matrix"]) for a, b in zip(ru, rt)) < 1e-6
PY

# The shipped example (configs/terrain_dem_tiled.yaml), its outputs here.
root=$(dirname -- "$here")
(cd "$root" && "$bin" align --config configs/terrain_dem_tiled.yaml --output="$tmp/example.json" \
  --dod="$tmp/example.tif" --tile_stats="$tmp/example_tiles.csv" \
  --patch_shifts="$tmp/example_shifts.csv" --quiet >"$tmp/stdout" 2>"$tmp/stderr")
rc=$?
checks=$((checks + 1))
[[ $rc -eq 0 && -s example.tif && -s example_tiles.csv && -s example_shifts.csv ]] &&
  python3 -c '
import json, sys
t = json.load(open(sys.argv[1]))["tiled"]
assert t["known"]["translation_error_cells"] < 0.05 and t["after"]["uncertainty"]["nodes"] > 4000, t
' example.json || fail "configs/terrain_dem_tiled.yaml"

# What is refused, each with one line naming the key.
echo "400000 5199600 300" >cloud.xyz
echo "400001 5199600 300" >>cloud.xyz
echo "400000 5199601 301" >>cloud.xyz
expect_refused "a tiled alignment is for two rasters" align a.bil cloud.xyz --max_memory=1G
expect_refused "flag '--aligned': not with flag '--max_memory'" align a.bil b.bil --max_memory=1G --aligned=out.tif
expect_refused "flag '--error_model': the variogram error model is not with flag '--max_memory' yet" align a.bil b.bil --max_memory=1G --error_model=variogram
expect_refused "at least 128M" align a.bil b.bil --max_memory=64M
expect_refused "flag '--sigma_moving': a σ raster does not go with flag '--max_memory' yet" \
  align a.bil b.bil --max_memory=1G --sigma_moving=a.bil
expect_refused "flag '--max_memory' expects a memory size" align a.bil b.bil --max_memory=lots
expect_refused "flag '--tile_stats': needs max_memory" align a.bil b.bil --tile_stats=t.csv
expect_refused "flag '--patch_shifts': needs max_memory" align a.bil b.bil --patch_shifts=t.csv
expect_refused "data domain only" align a.bil b.bil --max_memory=1G --domain=hull
[[ ! -e out.tif && ! -e t.csv ]] || fail "a refused run wrote an output"

echo "$checks checks, $failures failures"
[[ $failures -eq 0 ]]

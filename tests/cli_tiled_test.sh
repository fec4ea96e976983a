#!/usr/bin/env bash
# `surfreg measure --tile=N` and `--max_memory=SIZE` (issue 24): two DEMs
# with nodata holes on different grids, measured tile by tile through
# windowed reads, give the untiled measure (every volume and area to 1e-9
# relative, the node and cell counts exactly) for tiles of several sizes,
# one of them smaller than a hole and one larger than the DEM; a memory
# budget picks a tile; what cannot be tiled yet is refused with one line.
# Usage: cli_tiled_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run, expect_refused
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

# A 240 x 180 DEM and B on another grid, with holes and a known change.
python3 "$(dirname -- "$(realpath -- "$0")")/make_tiled_pair.py" || exit 2

run measure a.asc b.asc --json
cp stdout untiled.json
[[ $rc -eq 0 ]] || fail "untiled measure: exit $rc"
for tile in 16 37 100 1000; do
  run measure a.asc b.asc --json --tile=$tile
  cp stdout "tile$tile.json"
  checks=$((checks + 1))
  python3 - untiled.json "tile$tile.json" "$tile" <<'EOF' || fail "--tile=$tile differs from the untiled measure"
import json, sys
u, t = (json.load(open(p)) for p in sys.argv[1:3])
assert t["tile"] == int(sys.argv[3]) and t["tiles"] >= 1, (t.get("tile"), t.get("tiles"))
assert 6000 < u["change"]["cut"] < 9000, u["change"]  # the bump: 3 pi 800 m3 = 7540 m3
for key in ("rho_d", "rho_d_axial", "overlap_area", "domain_area_a", "domain_area_b", "weight_integral",
            "mean_abs_dz", "signed_volume", "volume_above", "volume_below"):
    assert abs(u[key] - t[key]) <= 1e-9 * abs(u[key]), (key, u[key], t[key])
for key in ("fill", "cut", "fill_area", "cut_area"):
    assert abs(u["change"][key] - t["change"][key]) <= 1e-9 * abs(u["change"][key]), (key, u["change"], t["change"])
for key in ("n_overlap_nodes", "n_cells", "n_points_a", "n_points_b"):
    assert u[key] == t[key], (key, u[key], t[key])
assert u["frame"] == t["frame"], (u["frame"], t["frame"])
print("  --tile=%s: %d tiles, rho_d %.12g (untiled %.12g)" % (sys.argv[3], t["tiles"], t["rho_d"], u["rho_d"]))
EOF
done

# The DoD on A's grid: written tile by tile, the very GeoTIFF cells of the
# untiled one (read back as cells through `transform` by the identity, whose
# shortest round-trip digits keep every Float32 bit): every value identical
# and nodata at the same cells, B − A reaching the bump's depth, nodata in
# A's holes. Tiles of 16 are smaller than A's large hole.
printf '1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n' >id.txt
for tile in 0 16 37 100; do
  run measure a.asc b.asc --tile=$tile --dod="dod$tile.tif" --quiet
  checks=$((checks + 1))
  [[ $rc -eq 0 ]] || fail "--dod with --tile=$tile: exit $rc"
  run transform "dod$tile.tif" --transform=id.txt --output="dod$tile.xyz"
done
checks=$((checks + 1))
python3 - dod0.xyz dod16.xyz dod37.xyz dod100.xyz <<'EOF' || fail "the tiled DoDs differ from the untiled one"
import sys
def cells(path):
    out = {}
    for line in open(path):
        line = line.split("#")[0].split()
        if line:
            out[(float(line[0]), float(line[1]))] = float(line[2])
    return out
untiled = cells(sys.argv[1])
assert 240 * 180 * 0.9 < len(untiled) < 240 * 180, len(untiled)  # A's holes are nodata
assert -3.05 < min(untiled.values()) < -2.9, min(untiled.values())
assert (1060.5, 4950.5) not in untiled  # the middle of A's large hole
for path in sys.argv[2:]:
    tiled = cells(path)
    assert set(tiled) == set(untiled), (path, len(tiled), len(untiled))
    differ = [k for k in untiled if tiled[k] != untiled[k]]
    assert not differ, (path, len(differ), [(k, tiled[k], untiled[k]) for k in differ[:3]])
EOF

# A memory budget picks the tile: 2 MiB / 700 bytes a cell -> 54 cells.
run measure a.asc b.asc --json --max_memory=2M
checks=$((checks + 1))
python3 -c 'import json, sys; t = json.load(open("stdout")); sys.exit(t["tile"] != 54 or t["tiles"] != 20)' ||
  fail "--max_memory=2M: expected tiles of 54 cells, 20 of them"

# Two lon/lat DEMs: moved sample by sample into the untiled run's frame
# (UTM, or ENU about their centre), tiled, the untiled measure.
for frame in auto enu; do
  run measure lla.asc llb.asc --json --frame=$frame
  cp stdout ll_untiled.json
  for tile in 16 37; do
    run measure lla.asc llb.asc --json --tile=$tile --frame=$frame
    checks=$((checks + 1))
    python3 - ll_untiled.json stdout "$frame" <<'PY' || fail "lon/lat --tile=$tile --frame=$frame differs from untiled"
import json, sys
u, t = (json.load(open(p)) for p in sys.argv[1:3])
assert u["frame"] == t["frame"] and ("UTM" in u["frame"]) == (sys.argv[3] == "auto"), (u["frame"], t["frame"])
assert u["length_unit"] == t["length_unit"] == "m" and u["overlap_area"] > 1e6, u
for key in ("rho_d", "rho_d_axial", "overlap_area", "domain_area_a", "domain_area_b", "signed_volume"):
    assert abs(u[key] - t[key]) <= 1e-9 * abs(u[key]), (key, u[key], t[key])
for key in ("n_overlap_nodes", "n_cells", "n_points_a", "n_points_b"):
    assert u[key] == t[key], (key, u[key], t[key])
PY
  done
done

# The change budget with both DEMs' σ as numbers: the untiled budget, tiled.
sigma=(--sigma_reference=0.05 --sigma_moving=0.08 --lod_confidence=0.95)
run measure a.asc b.asc --json "${sigma[@]}"
cp stdout budget_untiled.json
for tile in 16 37; do
  run measure a.asc b.asc --json --tile=$tile "${sigma[@]}"
  checks=$((checks + 1))
  python3 - budget_untiled.json stdout <<'PY' || fail "--tile=$tile: the change budget differs from the untiled one"
import json, sys
u, t = (json.load(open(p))["change"]["uncertainty"] for p in sys.argv[1:3])
assert u["cut_nodes"] > 1000 and u["cut_sigma_independent"] > 0, u
for key, value in u.items():
    if isinstance(value, str) or key.endswith("_nodes") or key == "nodes":
        assert t[key] == value, (key, value, t[key])
    else:
        assert abs(t[key] - value) <= 1e-9 * max(abs(value), 1.0), (key, value, t[key])
PY
done

# error_model variogram: the model and its budget, tiled as untiled (σ estimated, or given as numbers).
for given in "" "--sigma_reference=0.05"; do
  run measure a.asc b.asc --json --error_model=variogram --lod_confidence=0.95 $given
  cp stdout variogram_untiled.json
  for tile in 16 37; do
    run measure a.asc b.asc --json --tile=$tile --error_model=variogram --lod_confidence=0.95 $given
    checks=$((checks + 1))
    python3 - variogram_untiled.json stdout <<'PY' || fail "--tile=$tile $given: the variogram budget differs from the untiled one"
import json, sys
u, t = (json.load(open(p))["change"]["uncertainty"] for p in sys.argv[1:3])
assert u["net_sigma_spatial"] > u["net_sigma_independent"] > 0 and u["variogram"]["stable_cells"] > 1000, u
def same(a, b, key):
    if isinstance(a, dict):
        assert a.keys() == b.keys(), key
        for k in a:
            same(a[k], b[k], key + "." + k)
    elif isinstance(a, list):
        assert len(a) == len(b), key
        for x, y in zip(a, b):
            same(x, y, key)
    elif isinstance(a, float):
        assert abs(a - b) <= 1e-9 * max(abs(a), 1.0), (key, a, b)
    else:
        assert a == b, (key, a, b)
same(u, t, "uncertainty")
PY
  done
done
expect_refused "flag '--error_model': the variogram error model is fitted on the whole DoD" \
  measure a.asc b.asc --tile=32 --error_model=variogram --shard=1/2 --partial=p.json

# What is not tiled yet, or cannot be: one line, exit 2 (expect_refused).
printf '1000 5000 1\n1100 5000 2\n1000 5100 3\n' >cloud.xyz
expect_refused "flag '--tile': tiles are for two rasters, but argument B is 'cloud.xyz', a cloud" \
  measure a.asc cloud.xyz --tile=32
expect_refused "flag '--tile': a tiled measure does not take --volume=union yet" \
  measure a.asc b.asc --tile=32 --volume=union
expect_refused "has a CRS and the reference has none" measure a.asc ll.asc --tile=32
expect_refused "flag '--tile' expects a tile side in cells of A, 16 to 32768" measure a.asc b.asc --tile=8
expect_refused "flag '--dod': the DoD is written on A's grid, but A ('cloud.xyz') is no raster" \
  measure cloud.xyz b.asc --dod=d.tif
expect_refused "flag '--dod': written as GeoTIFF; expected a name ending in .tif" \
  measure a.asc b.asc --tile=32 --dod=d.png
run transform a.asc --transform=id.txt --output=a.tif
expect_refused "flag '--dod': 'a.tif' is also an input" measure a.tif b.asc --tile=32 --dod=a.tif
expect_refused "flag '--sigma_moving': a σ raster does not go with flag '--tile' yet" \
  measure a.asc b.asc --tile=32 --sigma_moving=a.tif
expect_refused "flag '--max_memory' expects a memory size such as 512M or 2G, got 'lots'" \
  measure a.asc b.asc --max_memory=lots
expect_refused "tiles of 1000 cells need about 667 MiB, more than flag '--max_memory' allows (64M)" \
  measure a.asc b.asc --tile=1000 --max_memory=64M

echo "$checks checks, $failures failed"
[[ $failures -eq 0 ]]

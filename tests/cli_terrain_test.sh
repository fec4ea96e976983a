#!/usr/bin/env bash
# End-to-end tests of `surfreg align` on terrain: the DEM example
# (configs/terrain_dem.yaml) recovers its known motion and reports dz
# statistics at the level of the added noise, writes the DoD GeoTIFF and the
# figures; bad rasters (no overlap, all nodata) and an unreadable CRS exit 2
# with one line and write nothing.
# Usage: cli_terrain_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$tmp/out
mkdir "$out"
failures=0

fail() {
  echo "FAIL: $*"
  echo "  exit code: $rc"
  sed 's/^/  stdout: /' "$tmp/stdout" | head -20
  sed 's/^/  stderr: /' "$tmp/stderr" | head -20
  failures=$((failures + 1))
}

run() {
  timeout 300 "$bin" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  rc=$?
}

expect_error() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $(wc -l <"$tmp/stderr") -ne 1 ]]; then
    fail "surfreg $*: expected exactly one line on stderr"
  elif ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: stderr does not mention '$text'"
  elif [[ -n $(ls -A "$out") ]]; then
    fail "surfreg $*: wrote $(ls -A "$out")"
  fi
}

# asc NAME XLL YLL VALUE: a 20 x 15 ESRI ASCII grid of 10 m cells, every cell VALUE.
asc() {
  {
    printf 'ncols 20\nnrows 15\nxllcorner %s\nyllcorner %s\ncellsize 10\nNODATA_value -9999\n' "$2" "$3"
    for _ in $(seq 15); do
      for c in $(seq 20); do printf '%s ' "$(( $4 == -9999 ? -9999 : $4 + c ))"; done
      printf '\n'
    done
  } >"$tmp/$1.asc"
}

# --- the example: known motion, noise level, outputs ---
sed "s#out/#$out/#" configs/terrain_dem.yaml >"$tmp/terrain.yaml"
run align --config "$tmp/terrain.yaml"
if [[ $rc -ne 0 ]]; then
  fail "terrain example"
else
  for f in terrain_dem_transform.json terrain_dem_dod.tif terrain_dem_dod.png \
           terrain_dem_histogram.png terrain_dem_change.csv; do
    [[ -s $out/$f ]] || fail "terrain example: no $f"
  done
  grep -q '^known motion: ' "$tmp/stdout" || fail "terrain example: no 'known motion' line"
  grep -q '^dz stable: ' "$tmp/stdout" || fail "terrain example: no dz statistics"
  python3 - "$out/terrain_dem_transform.json" "$out/terrain_dem_dod.tif" <<'PY' || fail "terrain example: figures"
import json, sys
t = json.load(open(sys.argv[1]))["terrain"]
known, before, after = t["known"], t["stable_before"], t["stable_after"]
noise = 0.5  # configs/data/make_terrain_example.py
checks = [
    (known["rotation_error_deg"] < 0.02, "rotation error %g deg" % known["rotation_error_deg"]),
    (known["translation_error_cells"] < 0.05, "translation error %g cells" % known["translation_error_cells"]),
    (0.5 * noise < after["nmad"] < 1.2 * noise, "NMAD after %g vs noise %g" % (after["nmad"], noise)),
    (before["nmad"] > 4 * after["nmad"], "NMAD before %g" % before["nmad"]),
    (abs(after["median"]) < 0.05, "median after %g" % after["median"]),
    (t["change"]["level_of_detection"] == 1.0, "lod"),
    (t["change"]["fill_uncertainty"] == 1.0 * t["change"]["fill_area"], "fill uncertainty"),
]
bad = [m for ok, m in checks if not ok]
print("terrain example:", "; ".join(m for _, m in checks))
# The GeoTIFF starts with a TIFF header.
head = open(sys.argv[2], "rb").read(4)
if head not in (b"II*\x00", b"MM\x00*"):
    bad.append("DoD is not a TIFF")
if bad:
    print("FAIL:", bad)
    sys.exit(1)
PY
fi
rm -rf "${out:?}"/*

# --- bad rasters and CRSs: exit 2, one line, nothing written ---
asc far 0 0 100
expect_error "do not overlap" align configs/data/volcano_dem.tif "$tmp/far.asc" \
  --moving_crs=EPSG:2193 --output="$out/t.json" --dod="$out/d.tif"
asc empty 1756000 5916500 -9999
expect_error "nodata" align configs/data/volcano_dem.tif "$tmp/empty.asc" --output="$out/t.json"
expect_error "CRS" align configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif \
  --reference_crs=EPSG:99999999 --output="$out/t.json"
expect_error "CRS" align configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif \
  --moving_crs=EPSG:4326 --output="$out/t.json"
expect_error "CRS" align configs/data/volcano_dem.tif "$tmp/far.asc" --output="$out/t.json"
expect_error "not a raster" align configs/data/volcano_a.xyz configs/data/volcano_dem_moved.tif \
  --dod="$out/d.tif"
expect_error ".tif" align configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif \
  --dod="$out/d.png"
expect_error "lod" align configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif --lod=-1

if [[ $failures -ne 0 ]]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all terrain CLI checks passed"

#!/usr/bin/env bash
# End-to-end tests of `surfreg align` on terrain: the DEM example
# (configs/terrain_dem.yaml) recovers its known motion and reports dz
# statistics at the level of the added noise, writes the DoD GeoTIFF and the
# figures; bad rasters (no overlap, all nodata) and an unreadable CRS exit 2
# with one line and write nothing; a stable-terrain mask raster removes
# exactly its zero, nodata and outside cells from the stable statistics.
# Usage: cli_terrain_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
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
checks=0

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
  # A metre CRS: the summary's lengths are in m, not in "units".
  grep -q '^translation: .* m  (shift of the moving centroid)$' "$tmp/stdout" ||
    fail "terrain example: the translation is not in m"
  grep -q '^known motion: .*translation [0-9.e-]* m (' "$tmp/stdout" ||
    fail "terrain example: the known motion's error is not in m"
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
# The stable-terrain map on the reference's grid: GeoTIFF and PNG.
run align --config "$tmp/terrain.yaml" --stable_map="$out/stable.png"
if [[ $rc -ne 0 ]] || [[ "$(head -c 8 "$out/stable.png" | od -An -tx1 | tr -d ' ')" != 89504e470d0a1a0a ]]; then
  fail "terrain example: --stable_map=stable.png: expected exit 0 and a PNG"
fi
run align --config "$tmp/terrain.yaml" --stable_map="$out/stable.tif"
if [[ $rc -ne 0 || ! -s "$out/stable.tif" ]]; then
  fail "terrain example: --stable_map=stable.tif: expected exit 0 and the GeoTIFF"
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

# --- a stable-terrain mask raster (mask_raster) ---
# mask_asc NAME ZERO: a 43 x 31 grid of 20 m cells over the example DEM (its
# last 10 m column outside), column 0 nodata, 1 elsewhere but 0 on the
# 5 x 5 block of columns 15-19, rows 10-14 (ZERO=1) or everywhere (ZERO=all).
mask_asc() {
  {
    printf 'ncols 43\nnrows 31\nxllcorner 1756000\nyllcorner 5916490\ncellsize 20\nNODATA_value -9999\n'
    for r in $(seq 0 30); do
      for c in $(seq 0 42); do
        if [[ $c -eq 0 ]]; then printf -- '-9999 '
        elif [[ $2 == all ]] || ((r >= 10 && r <= 14 && c >= 15 && c <= 19)); then printf '0 '
        else printf '1 '; fi
      done
      printf '\n'
    done
  } >"$tmp/$1.asc"
}
mask_asc stable 1
dem=(configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif --covariance=false)
run align "${dem[@]}" --output="$out/plain.json" --change_csv="$out/plain.csv"
[[ $rc -eq 0 ]] || fail "mask raster: the run without it"
run align "${dem[@]}" --mask_raster="$tmp/stable.asc" --output="$out/masked.json" \
  --change_csv="$out/masked.csv"
if [[ $rc -ne 0 ]]; then
  fail "mask raster"
else
  python3 - "$out" <<'PY' || fail "mask raster: stable samples"
import csv, json, math, sys
out = sys.argv[1]
def region(x, y):  # reference cells weighted 0: nodata column, outside, the zero block
    return x < 1756020 or x > 1756860 or (1756300 < x < 1756400 and 5916810 < y < 5916910)
plain = list(csv.DictReader(open(out + "/plain.csv")))
masked = list(csv.DictReader(open(out + "/masked.csv")))
inside = [r for r in plain if region(float(r["x"]), float(r["y"]))]
# Before alignment the motion is the same in both runs: the count of stable
# samples with a dz falls by exactly the region's samples with a dz.
expected = sum(1 for r in inside if math.isfinite(float(r["dz_before"])))
n = [json.load(open(out + f))["terrain"]["stable_before"]["count"] for f in ("/plain.json", "/masked.json")]
wrong = [r for r in masked if (r["stable"] == "1") == region(float(r["x"]), float(r["y"]))]
print("mask raster: stable before %d -> %d, %d region samples with dz (%d in the region), %d flags wrong"
      % (n[0], n[1], expected, len(inside), len(wrong)))
if n[0] - n[1] != expected or len(wrong) != 0 or len(masked) != 5307 or expected < 200:
    sys.exit(1)
PY
fi
rm -rf "${out:?}"/*
printf '1756100 5916600\n1756500 5916600\n1756500 5917000\n' >"$tmp/poly.txt"
expect_error "not both" align "${dem[@]}" --mask_raster="$tmp/stable.asc" --mask="$tmp/poly.txt" \
  --output="$out/t.json"
mask_asc zero all
expect_error "no sample of the reference" align "${dem[@]}" --mask_raster="$tmp/zero.asc" \
  --output="$out/t.json"
expect_error "mask_raster" align "${dem[@]}" --mask_raster="$tmp/missing.asc" --output="$out/t.json"

# --- the shipped change study with sigma per DEM runs and writes its outputs ---
sed "s#out/#$out/#" configs/terrain_change_uncertainty.yaml >"$tmp/change.yaml"
run align --config "$tmp/change.yaml"
if [[ $rc -ne 0 ]]; then
  fail "change study example"
else
  for f in terrain_change_transform.json terrain_change_dod.tif terrain_change_dod_sigma.tif \
           terrain_change_dod_thresholded.tif terrain_change_dod.png terrain_change_histogram.png \
           terrain_change_variogram.png; do
    [[ -s $out/$f ]] || fail "change study example: no $f"
  done
  python3 - "$out/terrain_change_transform.json" <<'PY' || fail "change study example: the budget"
import json, math, sys
b = json.load(open(sys.argv[1]))["terrain"]["change"]["uncertainty"]
# Every node has sigma_DoD = sqrt(0.3^2 + 0.5^2); the surveys differ by noise
# only, so detected change is a few percent of the nodes and the net is
# within its independent error of 0.
ok = (abs(b["sigma_dod_median"] - math.sqrt(0.34)) < 1e-12 and 0 < b["fill_nodes"] + b["cut_nodes"] < 0.05 * b["nodes"]
      and abs(b["net"]) < 3 * b["net_sigma_independent"] and b["net_sigma_correlated"] > b["net_sigma_independent"]
      # every node may be detected falsely: more than the detected nodes alone
      and b["error_model"] == "variogram" and b["net_sigma_spatial"] > b["net_sigma_independent"]
      and b["net_sigma_total"] >= b["net_sigma_spatial"])
print("change study: %d + %d of %d nodes, net %.1f +/- %.1f / %.1f, spatial %.1f" % (b["fill_nodes"], b["cut_nodes"],
      b["nodes"], b["net"], b["net_sigma_independent"], b["net_sigma_correlated"], b["net_sigma_spatial"]))
sys.exit(0 if ok else 1)
PY
fi
rm -rf "${out:?}"/*

# --- uncertainty of change: sigma per DEM, a confidence, closed forms ---
# grid NAME XLL VALUE...: 20 x 15 cells of 10 m (EPSG:2193 by flag), z = 100 + column,
# minus 3 on the block of columns 4-8, rows 3-6 (20 nodes) and plus 2 on
# columns 12-14, rows 8-10 (9 nodes) when CHANGE=1; a sigma grid when KIND=sigma
# (0.4 everywhere, VALUE on columns 4-5 of the -3 block: 8 nodes).
grid() {
  python3 - "$tmp/$1.asc" "$2" "$3" "$4" <<'PY'
import sys
path, xll, kind, value = sys.argv[1], float(sys.argv[2]), sys.argv[3], float(sys.argv[4])
rows = []
for r in range(15):
    row = []
    for c in range(20):
        if kind == "sigma":
            v = value if (4 <= c <= 5 and 3 <= r <= 6) else 0.4
        else:
            v = 100.0 + c
            if kind == "change" and 4 <= c <= 8 and 3 <= r <= 6: v -= 3
            if kind == "change" and 12 <= c <= 14 and 8 <= r <= 10: v += 2
        row.append("%g" % v)
    rows.append(" ".join(row))
open(path, "w").write("ncols 20\nnrows 15\nxllcorner %.3f\nyllcorner 5916500\ncellsize 10\n"
                      "NODATA_value -9999\n" % xll + "\n".join(rows) + "\n")
PY
}
grid before 1756000 plain 0
grid after 1756000 change 0
grid sigma_ok 1756000 sigma 2.0
grid sigma_shifted 1756005 sigma 0.4
grid sigma_negative 1756000 sigma -1
change=("$tmp/before.asc" "$tmp/after.asc" --reference_crs=EPSG:2193 --moving_crs=EPSG:2193
        --free=tz --covariance=false --sigma_reference=0.3 --lod_confidence=0.95)
run align "${change[@]}" --covariance=true --sigma_moving=0.4 --output="$out/u.json" --dod_sigma="$out/s.tif" \
  --dod_thresholded="$out/t.tif" --histogram_png="$out/h.png" --dod_png="$out/d.png"
[[ $rc -eq 0 ]] || fail "uncertainty: constant sigmas"
run align "${change[@]}" --sigma_moving="$tmp/sigma_ok.asc" --output="$out/r.json"
[[ $rc -eq 0 ]] || fail "uncertainty: a sigma raster"
python3 - "$out" <<'PY' || fail "uncertainty: closed forms"
import json, math, sys
out = sys.argv[1]
t = 1.959963984540054  # the two-sided 95% normal quantile
a = 100.0              # every changed node is an inner node: its cell, 10 m x 10 m
bad = []
def close(name, got, want, relative=1e-9):
    if not abs(got - want) <= relative * max(1.0, abs(want)):
        bad.append("%s: %r, expected %r" % (name, got, want))
u = json.load(open(out + "/u.json"))
b = u["terrain"]["change"]["uncertainty"]
s = 0.5  # sqrt(0.3^2 + 0.4^2)
close("t", b["t"], t)
close("sigma_dod_median", b["sigma_dod_median"], s)
close("fill", b["fill"], 2 * a * 9)
close("cut", b["cut"], 3 * a * 20)
close("net", b["net"], 2 * a * 9 - 3 * a * 20)
close("fill_area", b["fill_area"], a * 9)
close("cut_area", b["cut_area"], a * 20)
close("fill_sigma_independent", b["fill_sigma_independent"], s * a * 3)
close("cut_sigma_independent", b["cut_sigma_independent"], s * a * math.sqrt(20))
close("net_sigma_independent", b["net_sigma_independent"], s * a * math.sqrt(29))
close("fill_sigma_correlated", b["fill_sigma_correlated"], s * a * 9)
close("net_sigma_correlated", b["net_sigma_correlated"], s * a * 29)
if u["terrain"]["change"]["fill"] <= 0: bad.append("no exact fill")
# The motion's own uncertainty: only tz is free and dz grows by exactly tz
# at every node, so the registration's share is sigma_tz times the areas.
stz = u["stddev"]["tz"]
if not stz > 0: bad.append("no sigma of tz")
close("fill_sigma_registration", b["fill_sigma_registration"], stz * a * 9)
close("cut_sigma_registration", b["cut_sigma_registration"], stz * a * 20)
close("net_sigma_registration", b["net_sigma_registration"], stz * a * 29)
close("net_sigma_total", b["net_sigma_total"], math.hypot(s * a * math.sqrt(29), stz * a * 29))
# Per-cell sigma: 8 of the -3 nodes have sigma_moving 2, so 1.96 sqrt(0.09 + 4) > 3.
r = json.load(open(out + "/r.json"))["terrain"]["change"]["uncertainty"]
s2 = math.sqrt(0.09 + 4.0)
close("raster cut", r["cut"], 3 * a * 12)
if r["cut_nodes"] != 12: bad.append("raster cut_nodes %r" % r["cut_nodes"])
close("raster fill", r["fill"], 2 * a * 9)
close("raster cut_sigma_correlated", r["cut_sigma_correlated"], s * a * 12, 1e-7)  # Float32 0.4
# The sigma GeoTIFF and the thresholded DoD are written.
for f in ("s.tif", "t.tif", "h.png", "d.png"):
    head = open(out + "/" + f, "rb").read(4)
    if head[:2] not in (b"II", b"MM", b"\x89P"):
        bad.append(f + " missing or not an image")
print("uncertainty: fill %g +/- %g / %g, cut %g +/- %g / %g; raster cut %g over %d nodes"
      % (b["fill"], b["fill_sigma_independent"], b["fill_sigma_correlated"], b["cut"],
         b["cut_sigma_independent"], b["cut_sigma_correlated"], r["cut"], r["cut_nodes"]))
if bad:
    print("FAIL:", bad)
    sys.exit(1)
PY
rm -rf "${out:?}"/*
# measure: the same budget for two DEMs already co-registered (no motion).
run measure "$tmp/before.asc" "$tmp/after.asc" --reference_crs=EPSG:2193 --moving_crs=EPSG:2193 \
  --sigma_reference=0.3 --sigma_moving=0.4 --lod_confidence=0.95 --json
if [[ $rc -ne 0 ]]; then
  fail "measure with sigma"
else
  python3 - "$tmp/stdout" <<'PY' || fail "measure with sigma: closed forms"
import json, math, sys
b = json.load(open(sys.argv[1]))["change"]["uncertainty"]
want = {"fill": 1800, "cut": 6000, "net": -4200, "fill_area": 900, "cut_area": 2000,
        "fill_sigma_independent": 150, "cut_sigma_independent": 50 * math.sqrt(20),
        "net_sigma_independent": 50 * math.sqrt(29), "net_sigma_correlated": 1450, "sigma_dod_median": 0.5}
bad = [k for k, v in want.items() if not abs(b[k] - v) <= 1e-9 * max(1, abs(v))]
print("measure with sigma: fill %g +/- %g, cut %g +/- %g%s" % (b["fill"], b["fill_sigma_independent"], b["cut"],
      b["cut_sigma_independent"], "; wrong: %s" % bad if bad else ""))
sys.exit(1 if bad else 0)
PY
fi
# change_mask: the budget over the 8 x 8 nodes of columns 10-17, rows 5-12 (the +2 block and no cut).
printf '1756100 5916520\n1756180 5916520\n1756180 5916600\n1756100 5916600\n' >"$tmp/roi.txt"
run measure "$tmp/before.asc" "$tmp/after.asc" --reference_crs=EPSG:2193 --moving_crs=EPSG:2193 \
  --sigma_reference=0.3 --sigma_moving=0.4 --lod_confidence=0.95 --change_mask="$tmp/roi.txt" --json
if [[ $rc -ne 0 ]]; then
  fail "measure --change_mask"
else
  python3 - "$tmp/stdout" <<'PY' || fail "measure --change_mask: closed forms"
import json, sys
b = json.load(open(sys.argv[1]))["change"]["uncertainty"]
want = {"nodes": 64, "fill_nodes": 9, "cut_nodes": 0, "fill": 1800, "cut": 0, "fill_sigma_independent": 150,
        "fill_sigma_correlated": 450, "net_sigma_correlated": 450}
bad = [k for k, v in want.items() if not abs(b[k] - v) <= 1e-9 * max(1, abs(v))]
print("change_mask: %d nodes, fill %g +/- %g%s" % (b["nodes"], b["fill"], b["fill_sigma_independent"],
      "; wrong: %s" % bad if bad else ""))
sys.exit(1 if bad or not b["change_mask"].endswith("roi.txt") else 0)
PY
fi
expect_error "change_mask" measure "$tmp/before.asc" "$tmp/after.asc" --change_mask="$tmp/roi.txt"
printf '0 0\n1 0\n1 1\n' >"$tmp/nowhere.txt"
expect_error "holds none of the reference's samples" measure "$tmp/before.asc" "$tmp/after.asc" \
  --reference_crs=EPSG:2193 --moving_crs=EPSG:2193 --sigma_reference=0.3 --change_mask="$tmp/nowhere.txt"
expect_error "lod_confidence" measure "$tmp/before.asc" "$tmp/after.asc" --lod_confidence=0.95
expect_error "not on the grid" align "${change[@]}" --sigma_moving="$tmp/sigma_shifted.asc" \
  --output="$out/t.json"
python3 - "$tmp/sigma_holes.asc" <<'PY'
import sys  # sigma nodata on the first 3 columns of every row
rows = [" ".join("-9999" if c < 3 else "0.2" for c in range(20)) for r in range(15)]
open(sys.argv[1], "w").write("ncols 20\nnrows 15\nxllcorner 1756000.000\nyllcorner 5916500\ncellsize 10\n"
                             "NODATA_value -9999\n" + "\n".join(rows) + "\n")
PY
expect_error "has no value at 45 of the 300 valid cells" align "${change[@]}" \
  --sigma_moving="$tmp/sigma_holes.asc" --output="$out/t.json"
expect_error "sigma_moving" align "${change[@]}" --sigma_moving=nan --output="$out/t.json"
: >"$tmp/sigma_empty.asc"
expect_error "cannot open as a raster" align "${change[@]}" --sigma_moving="$tmp/sigma_empty.asc" \
  --output="$out/t.json"
expect_error "negative" align "${change[@]}" --sigma_moving="$tmp/sigma_negative.asc" \
  --output="$out/t.json"
expect_error "sigma_reference" align "${change[@]/--sigma_reference=0.3/--sigma_reference=-0.3}" \
  --output="$out/t.json"
expect_error "lod_confidence" align "${change[@]/--lod_confidence=0.95/--lod_confidence=1.5}" \
  --output="$out/t.json"
expect_error "needs the DEMs' vertical errors" align "$tmp/before.asc" "$tmp/after.asc" \
  --reference_crs=EPSG:2193 --moving_crs=EPSG:2193 --lod_confidence=0.9 --output="$out/t.json"
expect_error "point cloud" align configs/data/volcano_a.xyz configs/data/volcano_b.xyz \
  --sigma_reference="$tmp/sigma_ok.asc" --output="$out/t.json"
expect_error "dod_sigma" align configs/data/volcano_a.xyz configs/data/volcano_b.xyz \
  --sigma_reference=0.2 --dod_sigma="$out/s.tif" --output="$out/t.json"

# --- error_model variogram: the spatially correlated budget between the two bounds ---
run measure configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif --error_model=variogram \
  --variogram_png="$out/variogram.png" --dod_sigma="$out/sigma.tif" --json
if [[ $rc -ne 0 ]]; then
  fail "measure --error_model=variogram"
else
  python3 - "$tmp/stdout" "$out/variogram.png" <<'PY' || fail "measure --error_model=variogram: bounds and keys"
import json, os, sys
u = json.load(open(sys.argv[1]))["change"]["uncertainty"]
v = u["variogram"]
# Without a threshold Var = sum a_i a_j s_i s_j rho_ij with 0 <= rho <= 1: between the bounds.
ok = (u["error_model"] == "variogram" and u["sigma_model"]["estimated"] is True
      and u["net_sigma_independent"] <= u["net_sigma_spatial"] <= u["net_sigma_correlated"]
      and v["stable_cells"] >= 1000 and len(v["sills"]) == 2 and len(v["ranges"]) == 2
      and len(v["lags"]) == len(v["gamma"]) > 3 and u["spatial_block"] == 1
      and os.path.getsize(sys.argv[2]) > 1000 and os.path.getsize(sys.argv[2].replace("variogram.png", "sigma.tif")) > 1000)
print("variogram: net +/- %g (independent %g, correlated %g), nugget %g, ranges %s"
      % (u["net_sigma_spatial"], u["net_sigma_independent"], u["net_sigma_correlated"], v["nugget"], v["ranges"]))
sys.exit(0 if ok else 1)
PY
fi
rm -rf "${out:?}"/*
expect_error "needs a raster reference" measure configs/data/volcano_a.xyz configs/data/volcano_b.xyz \
  --error_model=variogram
expect_error "stable cells with a DoD value, and the variogram error model needs at least 1000" measure "$tmp/before.asc" "$tmp/after.asc" --error_model=variogram
expect_error "error_model" measure "$tmp/before.asc" "$tmp/after.asc" --error_model=kriging
expect_error "dod_sigma': needs the DEMs' vertical errors" measure "$tmp/before.asc" "$tmp/after.asc" \
  --dod_sigma="$out/s.tif"
expect_error "needs --error_model=variogram" measure "$tmp/before.asc" "$tmp/after.asc" \
  --variogram_png="$out/v.png"
expect_error "needs error_model: variogram" align "${change[@]}" --variogram_png="$out/v.png" \
  --output="$out/t.json"

# --- lon/lat DEMs in --manifest and sweep: the metric frame, as a single align ---
# Two 40 x 30 grids of 0.001 deg near Auckland (UTM 60S), B = A + 3 m.
python3 - "$tmp" <<'PY'
import math, sys
tmp = sys.argv[1]
wgs84 = ('GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,'
         '298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]]')
for name, dz in (("ll_a", 0.0), ("ll_b", 3.0)):
    with open(f"{tmp}/{name}.asc", "w") as f:
        f.write("ncols 40\nnrows 30\nxllcorner 174.75\nyllcorner -36.88\ncellsize 0.001\n"
                "NODATA_value -9999\n")
        for r in range(30):
            f.write(" ".join(repr(100 + 20 * math.sin(c / 4) * math.cos(r / 5) + 0.5 * c + dz)
                             for c in range(40)) + "\n")
    open(f"{tmp}/{name}.prj", "w").write(wgs84)
open(f"{tmp}/ll.csv", "w").write(f"reference,moving,output\n{tmp}/ll_a.asc,{tmp}/ll_b.asc,{tmp}/out/ll.json\n")
open(f"{tmp}/ll_sweep.yaml", "w").write(
    f"pairs:\n  - name: ll\n    reference: {tmp}/ll_a.asc\n    moving: {tmp}/ll_b.asc\n"
    "    truth: {rotation_deg: [0, 0, 0], translation: [0, 0, -3]}\n"
    f"settings:\n  covariance: false\nsweep:\n  cost: [volume]\noutput: {tmp}/out/ll_sweep.csv\n"
    "perturbations:\n  rotation_deg: [1]\n  shift_spacings: [3]\n  directions: 2\n  seed: 1\n")
PY
run align --manifest="$tmp/ll.csv" --covariance=false --output="$out/ll_summary.csv"
if [[ $rc -ne 0 ]]; then
  fail "lon/lat manifest"
else
  python3 - "$out/ll.json" <<'PY' || fail "lon/lat manifest: frame and translation in metres"
import json, sys
j = json.load(open(sys.argv[1]))
frame, t = j["terrain"]["frame"], j["translation"]
print("lon/lat manifest: %s; translation %s" % (frame, t))
ok = frame.startswith("UTM zone 60S") and abs(t[2] + 3) < 1e-3 and abs(t[0]) < 0.5 and abs(t[1]) < 0.5
sys.exit(0 if ok else 1)
PY
fi
run sweep --config "$tmp/ll_sweep.yaml"
if [[ $rc -ne 0 ]]; then
  fail "lon/lat sweep"
else
  python3 - "$out/ll_sweep.csv" <<'PY' || fail "lon/lat sweep: errors in metres"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
worst = max(float(r["translation_error"]) for r in rows)
start = [float(r["perturbation_spacings"]) for r in rows]
print("lon/lat sweep: %d runs from %s spacings away, worst translation error %.3g m" % (len(rows), start, worst))
# Spacings and errors in metres: a 0.001 deg cell is about 89 x 111 m here.
ok = len(rows) == 2 and all(r["success"] == "true" for r in rows) and worst < 0.5
sys.exit(0 if ok else 1)
PY
fi
# The aligned file of a lon/lat pair is in the metric frame, and says so.
run align "$tmp/ll_a.asc" "$tmp/ll_b.asc" --covariance=false --aligned="$out/ll_aligned.xyz"
if [[ $rc -ne 0 ]] || ! grep -q "^# coordinates: UTM zone 60S" "$out/ll_aligned.xyz" ||
   ! grep -q "matrix (moving -> reference, in those coordinates" "$out/ll_aligned.xyz" ||
   grep -q "input coordinates" "$out/ll_aligned.xyz"; then
  fail "lon/lat --aligned: expected a header naming UTM zone 60S as its coordinates"
fi
rm -rf "${out:?}"/*

if [[ $failures -ne 0 ]]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all terrain CLI checks passed"

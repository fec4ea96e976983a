#!/usr/bin/env bash
# End-to-end tests of transform files and `surfreg transform`: a cloud moved
# by a known matrix (text, commas, JSON) lands on the points python3
# computes; --inverse brings it back; align's matrix_txt equals its JSON's
# matrix and pdal_matrix, and `transform` of the moving cloud by it is what
# --aligned writes; initial_transform from a previous align starts at the
# solution; a DEM moved by whole cells onto its own grid is the shifted DEM
# with nodata where nothing moved in; align --aligned=x.tif of two DEMs is
# the moving DEM on the reference's grid (projected, and lon/lat aligned in
# UTM); a UTM cloud against a lon/lat reference aligns to the motion of the
# pair given in UTM both, and a lon/lat GeoJSON mask over UTM surfaces is
# the same rings in UTM; bad input is exit 2 with one line.
# Usage: cli_transform_test.sh SURFREG_BINARY
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
ref=configs/data/volcano_a.xyz
mov=configs/data/volcano_moved.xyz
dem=configs/data/volcano_dem.tif
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$tmp/out  # outputs of the error cases go here: it must stay empty
mkdir "$out"
failures=0
checks=0

# expect_error TEXT ARGS...: exit 2, one stderr line "surfreg: error: ..."
# with TEXT, nothing written to $out.
expect_error() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $(wc -l <"$tmp/stderr") -ne 1 ]]; then
    fail "surfreg $*: expected exactly one line on stderr"
  elif ! grep -q '^surfreg: error: ' "$tmp/stderr"; then
    fail "surfreg $*: stderr does not start with 'surfreg: error: '"
  elif ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: stderr does not mention '$text'"
  elif [[ -n $(ls -A "$out") ]]; then
    fail "surfreg $*: wrote $(ls -A "$out")"
  fi
}

# compare A B TOL [MATRIX]: the points of A (each moved by MATRIX, a file of
# 16 numbers, if given) equal B's, in order, to TOL relative to max(1, |p|).
compare() {
  python3 - "$@" <<'PY'
import sys
def points(path):
    out = []
    for line in open(path):
        line = line.split("#")[0].split()
        if line:
            out.append([float(v) for v in line[:3]])
    return out
a, b, tol = points(sys.argv[1]), points(sys.argv[2]), float(sys.argv[3])
if len(sys.argv) > 4:
    m = [float(v) for v in open(sys.argv[4]).read().replace(",", " ").split()]
    a = [[sum(m[4 * i + j] * (p + [1.0])[j] for j in range(4)) for i in range(3)] for p in a]
if len(a) != len(b):
    sys.exit("%d points vs %d" % (len(a), len(b)))
worst = max(abs(u - v) / max(1.0, abs(u)) for p, q in zip(a, b) for u, v in zip(p, q))
if worst > tol:
    sys.exit("points differ by %g relative (> %g)" % (worst, tol))
PY
}

# --- a cloud moved by a known matrix, read as text, with commas, as JSON ---
python3 - "$tmp" <<'PY'
import math, sys, json
t = sys.argv[1]
a, axis = 0.4, (0.2, -0.5, 0.84)
n = math.sqrt(sum(v * v for v in axis))
x, y, z = (v / n for v in axis)
c, s = math.cos(a), math.sin(a)
r = [[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]]
m = [r[0] + [1234.5], r[1] + [-987.25], r[2] + [42.125], [0, 0, 0, 1]]
open(t + "/m.txt", "w").write("".join(" ".join("%.17g" % v for v in row) + "\n" for row in m))
open(t + "/m.csv", "w").write("# CloudCompare-style, with commas\n" +
                              "".join(",".join("%.17g" % v for v in row) + "\n" for row in m))
json.dump({"matrix": m, "verdict": "converged_improved"}, open(t + "/m.json", "w"))
# A shear and a mirror: not rigid motions.
open(t + "/shear.txt", "w").write("1 0.2 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
open(t + "/mirror.txt", "w").write("-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
open(t + "/short.txt", "w").write("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0\n")
open(t + "/id.txt", "w").write("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
open(t + "/shift.txt", "w").write("1 0 0 20\n0 1 0 -10\n0 0 1 0\n0 0 0 1\n")  # 2 and 1 cells
PY
run transform "$ref" --transform="$tmp/m.txt" --output="$tmp/moved.xyz"
[[ $rc -eq 0 ]] || fail "transform by m.txt"
compare "$ref" "$tmp/moved.xyz" 1e-12 "$tmp/m.txt" || fail "transform: points are not M p"
for t in m.csv m.json; do
  run transform "$ref" --transform="$tmp/$t" --output="$tmp/moved_$t.xyz"
  [[ $rc -eq 0 ]] || fail "transform by $t"
  compare "$tmp/moved.xyz" "$tmp/moved_$t.xyz" 0 || fail "transform by $t differs from m.txt"
done
# A wide text cloud: --columns picks x, y, z as for align.
python3 - "$ref" "$tmp/wide.csv" <<'PY'
import sys
with open(sys.argv[2], "w") as out:
    out.write("id;X;Y;Z;intensity\n")
    for i, line in enumerate(l.split("#")[0].split() for l in open(sys.argv[1])):
        if line:
            out.write("%d;%s;%s;%s;7\n" % (i, line[0], line[1], line[2]))
PY
run transform "$tmp/wide.csv" --columns=X,Y,Z --transform="$tmp/m.txt" --output="$tmp/moved_wide.xyz"
[[ $rc -eq 0 ]] || fail "transform --columns"
compare "$tmp/moved.xyz" "$tmp/moved_wide.xyz" 0 || fail "transform --columns differs from the xyz"
run transform "$tmp/moved.xyz" --transform="$tmp/m.txt" --inverse --output="$tmp/back.ply"
[[ $rc -eq 0 ]] || fail "transform --inverse"
run transform "$tmp/back.ply" --transform="$tmp/id.txt" --output="$tmp/back.xyz"
compare "$ref" "$tmp/back.xyz" 1e-9 || fail "transform then --inverse is not the input"

# --- align: matrix_txt, pdal_matrix, and transform = aligned ---
run align "$ref" "$mov" --covariance=false --output="$tmp/a.json" --matrix_txt="$tmp/a.txt" \
  --aligned="$tmp/aligned.xyz"
[[ $rc -eq 0 ]] || fail "align with matrix_txt"
grep -q "^matrix_txt: " "$tmp/stdout" || fail "align summary does not name matrix_txt"
python3 - "$tmp/a.json" "$tmp/a.txt" <<'PY' || fail "matrix_txt / pdal_matrix differ from the JSON's matrix"
import json, sys
j = json.load(open(sys.argv[1]))
matrix = [v for row in j["matrix"] for v in row]
text = [float(v) for v in open(sys.argv[2]).read().split()]
lines = open(sys.argv[2]).read().splitlines()
pdal = [float(v) for v in j["pdal_matrix"].split(" ")]
assert len(lines) == 4 and all(len(l.split()) == 4 for l in lines), lines
assert text == matrix, (text, matrix)
assert pdal == matrix, (pdal, matrix)
PY
run transform "$mov" --transform="$tmp/a.txt" --output="$tmp/by_txt.xyz"
compare "$tmp/aligned.xyz" "$tmp/by_txt.xyz" 1e-12 || fail "transform by matrix_txt is not --aligned"

# --- initial_transform: a previous solution is the start ---
# The measure before equals the previous run's after (the same pose), and
# the run ends where that one did; with the axial cost in a few iterations.
run align "$ref" "$mov" --covariance=false --cost=axial --output="$tmp/c.json"
for start in a.json a.txt c.json; do
  cost=volume
  [[ $start == c.json ]] && cost=axial
  run align "$ref" "$mov" --covariance=false --cost=$cost --initial_transform="$tmp/$start" \
    --output="$tmp/b_$start.json"
  [[ $rc -eq 0 ]] || fail "align --initial_transform=$start"
  first=$tmp/${start%.*}.json
  python3 - "$first" "$tmp/b_$start.json" <<'PY' || fail "initial_transform=$start does not start at the solution"
import json, sys
a, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
before, after = b["before"]["mean_abs_dz"], a["after"]["mean_abs_dz"]
assert abs(before - after) <= 1e-9 * after, (before, after)
if b["cost"] == "axial":
    assert b["iterations"] <= 3, b["iterations"]
worst = max(abs(u - v) for r, s in zip(a["matrix"], b["matrix"]) for u, v in zip(r, s))
assert worst < 1e-4, worst
PY
done

if has_part gdal; then  # rasters and CRSs: not in a build without GDAL
# cells(path[, digits]): a written cloud's {(x, y): z} (x, y rounded to digits).
cat >"$tmp/cells.py" <<'PY'
def cells(path, digits=None):
    out = {}
    for line in open(path):
        line = line.split("#")[0].split()
        if line:
            x, y = float(line[0]), float(line[1])
            out[(x, y) if digits is None else (round(x, digits), round(y, digits))] = float(line[2])
    return out
PY
# --- a DEM moved by whole cells, on its own grid: the shifted DEM ---
run transform "$dem" --transform="$tmp/shift.txt" --output="$tmp/shift.tif"
[[ $rc -eq 0 ]] || fail "transform of a DEM"
run transform "$tmp/shift.tif" --transform="$tmp/id.txt" --output="$tmp/shift_cells.xyz"
run transform "$dem" --transform="$tmp/id.txt" --output="$tmp/dem_cells.xyz"
python3 - "$tmp/dem_cells.xyz" "$tmp/shift_cells.xyz" <<'PY' || fail "the shifted DEM is not the DEM shifted by whole cells"
import os, sys
sys.path.insert(0, os.path.dirname(sys.argv[1]))
from cells import cells
dem, moved = cells(sys.argv[1]), cells(sys.argv[2])
# Every cell of the grid whose source cell (20 m west, 10 m north) is data.
expected = {(x + 20, y - 10): z for (x, y), z in dem.items() if (x + 20, y - 10) in dem}
assert set(moved) == set(expected), (len(moved), len(expected))  # nodata where nothing moved in
assert len(moved) < len(dem)
worst = max(abs(moved[k] - expected[k]) for k in moved)
assert worst <= 1e-9, worst
PY
run transform "$ref" --transform="$tmp/shift.txt" --grid="$dem" --output="$tmp/cloud.tif"
[[ $rc -eq 0 && -s $tmp/cloud.tif ]] || fail "transform of a cloud onto --grid"
# --band and --window read a part of a raster INPUT (as measure and align
# do), and that part's grid is the output's: by the identity, those cells.
run transform "$dem" --transform="$tmp/id.txt" --band=1 --window=10,5,20,15 --output="$tmp/part.tif"
[[ $rc -eq 0 ]] || fail "transform --band --window"
run transform "$tmp/part.tif" --transform="$tmp/id.txt" --output="$tmp/part_cells.xyz"
checks=$((checks + 1))
python3 - "$tmp/part_cells.xyz" "$tmp/dem_cells.xyz" <<'PY' || fail "transform --window: expected the window's cells of the DEM"
import os, sys
sys.path.insert(0, os.path.dirname(sys.argv[1]))
from cells import cells
part, dem = cells(sys.argv[1]), cells(sys.argv[2])
assert 0 < len(part) <= 20 * 15 and all(part[k] == dem[k] for k in part), len(part)
PY
expect_error "band 2 of 1" transform "$dem" --transform="$tmp/id.txt" --band=2 --output="$tmp/x.tif"
expect_error "flag '--window': INPUT is a cloud, not a raster" \
  transform "$ref" --transform="$tmp/id.txt" --window=0,0,5,5 --output="$tmp/x.xyz"

# --- align --aligned=x.tif: the moving DEM on the reference's grid ---
# It equals the moving DEM moved by the known motion onto that grid (transform
# with configs/data/volcano_dem_truth.txt, --grid) within the alignment's
# error, on the same cells, all of them cells of the reference.
run align "$dem" configs/data/volcano_dem_moved.tif --covariance=false --aligned="$tmp/al.tif"
[[ $rc -eq 0 ]] || fail "align --aligned=x.tif"
run transform configs/data/volcano_dem_moved.tif --transform=configs/data/volcano_dem_truth.txt \
  --grid="$dem" --output="$tmp/truth.tif"
[[ $rc -eq 0 ]] || fail "transform by the truth onto --grid"
for f in al truth; do
  run transform "$tmp/$f.tif" --transform="$tmp/id.txt" --output="$tmp/${f}_cells.xyz"
done
python3 - "$tmp/al_cells.xyz" "$tmp/truth_cells.xyz" "$tmp/dem_cells.xyz" <<'PY' || fail "aligned GeoTIFF is not the moving DEM on the reference's grid"
import os, sys
sys.path.insert(0, os.path.dirname(sys.argv[1]))
from cells import cells
aligned, truth, reference = (cells(p) for p in sys.argv[1:4])
assert set(aligned) == set(truth) and set(aligned) <= set(reference), (len(aligned), len(truth))
assert len(aligned) > 0.9 * len(reference), len(aligned)
worst = max(abs(aligned[k] - truth[k]) for k in aligned)
assert worst < 0.2, worst  # the known-motion error is ~0.01 cell: a few cm on these slopes
PY

# --- the same for lon/lat DEMs (align works in UTM): on the reference's lon/lat grid ---
# A: five Gaussian hills (20-50 m) on a slope, 80 x 80 cells of 0.0005 deg
# near Auckland; B: the same 0.0013 deg east, 0.0009 deg south, 2 m higher. The aligned B
# on A's grid is A again (to the alignment's and the sampling's error).
python3 - "$tmp" <<'PY' || fail "cannot make the lon/lat DEMs"
import math, sys
tmp = sys.argv[1]
wgs84 = ('GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,'
         '298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]]')
n, cell, west, south = 80, 0.0005, 174.75, -36.90
# Hills of several sizes: every motion, rotation about z too, well determined.
bumps = [(0, 0, 50, 1), (1.5, 1, 30, 0.5), (-1.2, 1.3, 25, 0.6), (1, -1.5, 20, 0.4), (-1.5, -1, 35, 0.7)]
def write(name, dlon, dlat, dz):
    with open(f"{tmp}/{name}.asc", "w") as f:
        f.write(f"ncols {n}\nnrows {n}\nxllcorner {west!r}\nyllcorner {south!r}\n"
                f"cellsize {cell!r}\nNODATA_value -9999\n")
        for r in range(n):
            lat = south + (n - r - 0.5) * cell
            row = []
            for c in range(n):
                lon = west + (c + 0.5) * cell
                u = (lon - dlon - (west + 0.02)) / 0.008
                v = (lat - dlat - (south + 0.02)) / 0.006
                z = 100 + dz + 5 * u
                for (bu, bv, height, width) in bumps:
                    z += height * math.exp(-((u - bu) ** 2 + (v - bv) ** 2) / width ** 2)
                row.append(repr(z))
            f.write(" ".join(row) + "\n")
    open(f"{tmp}/{name}.prj", "w").write(wgs84)
write("hill_a", 0, 0, 0)
write("hill_b", 0.0013, -0.0009, 2)
PY
run align "$tmp/hill_a.asc" "$tmp/hill_b.asc" --covariance=false --aligned="$tmp/hill_al.tif" --json
checks=$((checks + 1))
if [[ $rc -ne 0 ]] || ! grep -q '"frame": "UTM zone 60S' "$tmp/stdout"; then
  fail "align of lon/lat DEMs --aligned=x.tif: expected exit 0 in the UTM 60S frame"
else
  for f in hill_a hill_al; do
    src="$tmp/$f.asc"; [[ $f == hill_al ]] && src="$tmp/hill_al.tif"
    run transform "$src" --transform="$tmp/id.txt" --output="$tmp/${f}_cells.xyz"
  done
  python3 - "$tmp/hill_al_cells.xyz" "$tmp/hill_a_cells.xyz" <<'PY' || fail "aligned lon/lat GeoTIFF is not the reference again"
import os, sys
sys.path.insert(0, os.path.dirname(sys.argv[1]))
from cells import cells
aligned, reference = (cells(p, 9) for p in sys.argv[1:3])
assert set(aligned) <= set(reference) and len(aligned) > 0.8 * len(reference), (len(aligned), len(reference))
worst = max(abs(aligned[k] - reference[k]) for k in aligned)
assert worst < 0.5, worst  # hills 280 m wide sampled every ~45 m: sampling error ~0.2 m
print("lon/lat aligned GeoTIFF: %d of %d cells, worst |dz| %.3f m" % (len(aligned), len(reference), worst))
PY
fi

# --- mixed CRSs: a UTM moving cloud against a lon/lat reference ---
cat >"$tmp/utm60s.py" <<'PY'
import math
a, f = 6378137.0, 1 / 298.257223563
n = f / (2 - f)
big_a = a / (1 + n) * (1 + n * n / 4 + n ** 4 / 64)
alpha = [n / 2 - 2 * n * n / 3 + 5 * n ** 3 / 16, 13 * n * n / 48 - 3 * n ** 3 / 5, 61 * n ** 3 / 240]
c = 2 * math.sqrt(n) / (1 + n)
def utm60s(lon, lat):
    phi, lam = math.radians(lat), math.radians(lon - 177.0)
    t = math.sinh(math.atanh(math.sin(phi)) - c * math.atanh(c * math.sin(phi)))
    xi, eta = math.atan2(t, math.cos(lam)), math.atanh(math.sin(lam) / math.sqrt(1 + t * t))
    e = eta + sum(al * math.cos(2 * j * xi) * math.sinh(2 * j * eta) for j, al in enumerate(alpha, 1))
    nn = xi + sum(al * math.sin(2 * j * xi) * math.cosh(2 * j * eta) for j, al in enumerate(alpha, 1))
    return 500000 + 0.9996 * big_a * e, 10000000 + 0.9996 * big_a * nn
PY
# B's samples in UTM 60S (Krüger's series, 3 terms: sub-millimetre) and A's
# both in lon/lat and in UTM 60S: B (UTM) against A (lon/lat) is brought
# into A's CRS and then into UTM 60S, so it must align to the motion of the
# pair given in UTM 60S both.
python3 - "$tmp" <<'PY' || fail "cannot make the mixed-CRS clouds"
import math, sys
tmp = sys.argv[1]
sys.path.insert(0, tmp)
from utm60s import utm60s
def cells(name):
    rows = open(f"{tmp}/{name}.asc").read().split("\n")[6:]
    n_cells, cell, west, south = 80, 0.0005, 174.75, -36.90
    for r, row in enumerate(rows[:n_cells]):
        for col, z in enumerate(row.split()):
            yield west + (col + 0.5) * cell, south + (n_cells - r - 0.5) * cell, float(z)
for name in ("hill_a", "hill_b"):
    with open(f"{tmp}/{name}_ll.xyz", "w") as ll, open(f"{tmp}/{name}_utm.xyz", "w") as utm:
        for lon, lat, z in cells(name):
            ll.write(f"{lon!r} {lat!r} {z!r}\n")
            x, y = utm60s(lon, lat)
            utm.write(f"{x!r} {y!r} {z!r}\n")
PY
run align "$tmp/hill_a_ll.xyz" "$tmp/hill_b_utm.xyz" --reference_crs=EPSG:4326 --moving_crs=EPSG:32760 \
  --covariance=false --matrix_txt="$tmp/mixed.txt" --json
cp "$tmp/stdout" "$tmp/mixed.json"
run align "$tmp/hill_a_utm.xyz" "$tmp/hill_b_utm.xyz" --reference_crs=EPSG:32760 --moving_crs=EPSG:32760 \
  --covariance=false --matrix_txt="$tmp/utm.txt"
checks=$((checks + 1))
python3 - "$tmp/mixed.txt" "$tmp/utm.txt" "$tmp/mixed.json" <<'PY' || fail "mixed CRSs: expected the motion of the pair in UTM 60S"
import json, math, sys
m, u = ([[float(v) for v in line.split()] for line in open(p) if line.strip()] for p in sys.argv[1:3])
frame = json.load(open(sys.argv[3]))["terrain"]["frame"]
assert frame.startswith("UTM zone 60S"), frame
rot = max(abs(m[i][k] - u[i][k]) for i in range(3) for k in range(3))
# Translations compared at the data (about 1.76e6, 5.91e6): R c + t.
cx, cy = 300000.0, 5915000.0
shift = max(abs(sum(m[i][k] * p for k, p in enumerate((cx, cy, 100))) + m[i][3]
                - sum(u[i][k] * p for k, p in enumerate((cx, cy, 100))) - u[i][3]) for i in range(3))
print("mixed CRSs against UTM: rotation entries within %.2g, shift at the data within %.3g m" % (rot, shift))
assert rot < 2e-5 and shift < 0.05, (rot, shift)  # sigma here: 1e-5 rad, 0.012 m
PY

# --- a vector mask in another CRS than the surfaces' ---
# A GeoJSON polygon with a hole (lon/lat, as GeoJSON always is) over the UTM
# pair, and the same rings with their vertices in UTM 60S as text: the
# mask's vertices are reprojected into the surfaces' CRS, so the measures
# agree (the vertices to a micrometre).
python3 - "$tmp" <<'PY' || fail "cannot make the lon/lat mask"
import json, sys
tmp = sys.argv[1]
sys.path.insert(0, tmp)
from utm60s import utm60s
outer = [(174.755, -36.895), (174.785, -36.895), (174.785, -36.865), (174.755, -36.865)]
hole = [(174.765, -36.885), (174.765, -36.875), (174.775, -36.875), (174.775, -36.885)]
rings = [outer + outer[:1], hole + hole[:1]]
json.dump({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},
           "geometry": {"type": "Polygon", "coordinates": rings}}]}, open(f"{tmp}/ll_mask.geojson", "w"))
with open(f"{tmp}/utm_mask.txt", "w") as f:
    for k, ring in enumerate((outer, hole)):
        if k:
            f.write(">\n")
        for lon, lat in ring:
            f.write("%r %r\n" % utm60s(lon, lat))
PY
run measure "$tmp/hill_a_utm.xyz" "$tmp/hill_b_utm.xyz" --reference_crs=EPSG:32760 --moving_crs=EPSG:32760 \
  --weights=mask:"$tmp/ll_mask.geojson" --json
cp "$tmp/stdout" "$tmp/mask_ll.json"
run measure "$tmp/hill_a_utm.xyz" "$tmp/hill_b_utm.xyz" --reference_crs=EPSG:32760 --moving_crs=EPSG:32760 \
  --weights=mask:"$tmp/utm_mask.txt" --json
checks=$((checks + 1))
python3 - "$tmp/mask_ll.json" "$tmp/stdout" <<'PY' || fail "a lon/lat mask over UTM surfaces: expected the UTM rings' measures"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["mask_rings"] == 2 and b["mask_rings"] == 2, (a.get("mask_rings"), b.get("mask_rings"))
for key in ("weight_integral", "rho_d", "signed_volume"):
    assert abs(a[key] - b[key]) <= 1e-6 * abs(b[key]), (key, a[key], b[key])
print("lon/lat mask over UTM: weight integral %.6g m2 (text rings %.6g)" % (a["weight_integral"], b["weight_integral"]))
PY

fi  # has_part gdal

# --- bad input: exit 2, one line, nothing written ---
expect_error "flag '--aligned': a GeoTIFF" align "$ref" "$mov" --aligned="$out/x.tif"

expect_error "flag '--transform' is required" transform "$ref" --output="$out/x.xyz"
expect_error "flag '--output' is required" transform "$ref" --transform="$tmp/m.txt"
expect_error "shear.txt: not a rigid motion: the 3 x 3 part is not a rotation" \
  transform "$ref" --transform="$tmp/shear.txt" --output="$out/x.xyz"
expect_error "mirror.txt: not a rigid motion: the 3 x 3 part is a reflection" \
  transform "$ref" --transform="$tmp/mirror.txt" --output="$out/x.xyz"
expect_error "short.txt: 15 numbers" transform "$ref" --transform="$tmp/short.txt" --output="$out/x.xyz"
expect_error "nothere.txt: cannot open" transform "$ref" --transform="$tmp/nothere.txt" --output="$out/x.xyz"
expect_error "expected a name ending in .xyz, .txt, .ply, .las or .tif" \
  transform "$ref" --transform="$tmp/m.txt" --output="$out/x.obj"
expect_error "needs a grid: give --grid=REF.tif" transform "$ref" --transform="$tmp/m.txt" --output="$out/x.tif"
expect_error "flag '--grid': a grid is only for a .tif output" \
  transform "$dem" --transform="$tmp/m.txt" --grid="$dem" --output="$out/x.xyz"
expect_error "flag '--classes': INPUT is a raster" transform "$dem" --classes=2 --transform="$tmp/m.txt" --output="$out/x.tif"
expect_error "has no classes" transform "$ref" --classes=2 --transform="$tmp/m.txt" --output="$out/x.xyz"
expect_error "is also an input" transform "$tmp/moved.xyz" --transform="$tmp/m.txt" --output="$tmp/moved.xyz"
# A mistyped flag is a usage error: the message, then where to find usage.
run transform "$ref" --transform="$tmp/m.txt" --inverted --output="$out/x.xyz"
[[ $rc -eq 2 ]] && grep -qF "unknown flag '--inverted' (did you mean '--inverse'?)" "$tmp/stderr" ||
  fail "transform --inverted: expected exit 2 and did-you-mean '--inverse'"
expect_error "flag '--initial_transform' and flag '--initial_translation' both set the start" \
  align "$ref" "$mov" --initial_transform="$tmp/a.txt" --initial_translation=1,0,0 --output="$out/t.json"
expect_error "flag '--initial_transform': $tmp/shear.txt: not a rigid motion" \
  align "$ref" "$mov" --initial_transform="$tmp/shear.txt" --output="$out/t.json"

echo "cli_transform_test: $checks checks, $failures failures"
[[ $failures -eq 0 ]]

#!/usr/bin/env bash
# End-to-end tests of `surfreg measure` on the sample pair in configs/data
# (volcano_a.xyz: the 87 x 61 grid; volcano_b.xyz: 4000 random points on its
# bilinear surface): the JSON contract, exact identities (A against itself, A
# against A shifted up, swapping A and B), the volume and weight modes, and
# the one-line error contract (exit 2).
# Usage: cli_measure_test.sh SURFREG_BINARY
# Needs python3 (standard library). Paths are relative to the project root
# (this script's parent folder), whatever the current directory.
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
a=configs/data/volcano_a.xyz
b=configs/data/volcano_b.xyz
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0

source "$(dirname -- "$(realpath -- "$0")")/measure_harness.sh"  # measure_json, check, expect_input_error

# expect_usage_error ARGS...: exit 2, one "surfreg: error:" line, then usage.
expect_usage_error() {
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif ! head -1 "$tmp/stderr" | grep -q '^surfreg: error: '; then
    fail "surfreg $*: stderr does not start with 'surfreg: error: '"
  elif [[ $(grep -c '^surfreg: error: ' "$tmp/stderr") -ne 1 ]]; then
    fail "surfreg $*: expected exactly one error line"
  elif ! grep -q 'usage: surfreg measure' "$tmp/stderr"; then
    fail "surfreg $*: no measure usage line on stderr"
  fi
}

# Test inputs derived from the pair (python, so the numbers stay exact).
python3 - "$a" "$b" "$tmp" <<'EOF' || { echo "FAIL: cannot make the test inputs"; exit 1; }
import sys
a, b, tmp = sys.argv[1:]
def rewrite(src, dst, fn):
    with open(src) as f, open(dst, "w") as out:
        for line in f:
            if line.startswith("#") or not line.strip():
                out.write(line)
            else:
                out.write(fn(*map(float, line.split())) + "\n")
# z + 1.5 exactly (the grid's heights are whole metres).
rewrite(a, tmp + "/a_up.xyz", lambda x, y, z: f"{x!r} {y!r} {z + 1.5!r}")
# B moved 10 km east: no overlap with A.
rewrite(b, tmp + "/b_far.xyz", lambda x, y, z: f"{x + 10000:.3f} {y:.3f} {z:.3f}")
with open(tmp + "/west.txt", "w") as f:  # the west half of the grid, as a closed ring
    f.write("# west half of volcano_a: x in [0, 430], y in [0, 600]\n"
            "0 0\n430 0\n430 600  # north-east corner\n\n0 600\n0 0\n")
with open(tmp + "/inner.txt", "w") as f:  # well inside B's hull
    f.write("20 20\n430 20\n430 580\n20 580\n")
with open(tmp + "/bad_line.txt", "w") as f:
    f.write("# a polygon\n0 0\n430 0\n430 6O0\n0 600\n")
with open(tmp + "/three_numbers.txt", "w") as f:
    f.write("0 0\n430 0 1\n0 600\n")
with open(tmp + "/two_vertices.txt", "w") as f:
    f.write("0 0\n430 0\n")
EOF

keys='["rho_d", "rho_d_axial", "rho_s", "overlap_area", "mean_abs_dz", "signed_volume",
       "volume_above", "volume_below", "n_points_a", "n_points_b", "n_overlap_nodes", "timings",
       "file_a", "file_b", "volume_mode", "weight_mode", "n_duplicates_a", "n_duplicates_b",
       "n_cells", "weight_integral", "domain", "domain_area_a", "domain_area_b",
       "excluded_area_a", "excluded_area_b", "frame", "crs_a", "crs_b", "length_unit", "change"]'
stages='["read", "triangulate", "domain", "spanning_tree", "locate", "interpolate", "volume",
         "total"]'

# --- the volcano pair ----------------------------------------------------------

if measure_json ab "$a" "$b"; then
  check "measure A B: keys, counts, overlap = B's data domain, small gap" "
ab = r('ab')
missing = [k for k in $keys if k not in ab] + ['timings.' + k for k in $stages if k not in ab['timings']]
assert not missing, missing
assert all(ab['timings'][k] >= 0 for k in $stages), ab['timings']
assert ab['file_a'] == '$a' and ab['file_b'] == '$b', (ab['file_a'], ab['file_b'])
assert ab['volume_mode'] == 'overlay' and ab['weight_mode'] == 'uniform', ab
assert ab['n_points_a'] == 5307 and ab['n_points_b'] == 4000, ab
assert ab['n_duplicates_a'] == 0 and ab['n_duplicates_b'] == 0, ab
assert ab['n_overlap_nodes'] > 4000 and ab['n_cells'] > 0, ab
hull_b = hull_area('$b')
print('  overlap_area %.6f m², hull of B %.6f m² (ratio %.9f)' % (ab['overlap_area'], hull_b, ab['overlap_area'] / hull_b))
# A (the whole grid) is data everywhere; B (4000 random points) loses its
# hull's outline slivers: Ω is B's data domain.
assert ab['domain'] == 'data', ab
assert close(ab['domain_area_a'], 860 * 600, 1e-12) and abs(ab['excluded_area_a']) < 1e-6, ab
assert close(ab['excluded_area_b'], hull_b - ab['domain_area_b'], 1e-9), (ab, hull_b)
assert 0.97 * hull_b < ab['domain_area_b'] < hull_b, (ab['domain_area_b'], hull_b)
assert close(ab['overlap_area'], ab['domain_area_b'], 1e-9), ab
print('  rho_d %.6f m³, rho_d_axial %.6f m, mean_abs_dz %.6f m, rho_s %.6g' % (ab['rho_d'], ab['rho_d_axial'], ab['mean_abs_dz'], ab['rho_s']))
print('  signed %.6f m³ = above %.6f - below %.6f' % (ab['signed_volume'], ab['volume_above'], ab['volume_below']))
assert ab['rho_d'] >= 0 and ab['rho_d_axial'] >= 0, ab
assert ab['overlap_area'] <= 860 * 600 * (1 + 1e-12), ab
assert close(ab['weight_integral'], ab['overlap_area'], 1e-12), ab
assert 0 < ab['mean_abs_dz'] < 2 and 0 < ab['rho_d_axial'] < 2, ab
assert close(ab['rho_d'], ab['mean_abs_dz'] * ab['overlap_area'], 1e-9), ab
assert close(ab['rho_s'], 1 / ab['rho_d'], 1e-12), ab
assert close(ab['rho_d'], ab['volume_above'] + ab['volume_below'], 1e-9), ab
assert abs(ab['signed_volume'] - (ab['volume_above'] - ab['volume_below'])) <= 1e-9 * ab['rho_d'], ab
"
fi

run measure "$a" "$b"
if [[ $rc -ne 0 ]]; then
  fail "measure A B (text): expected exit 0"
elif [[ -s "$tmp/stderr" ]]; then
  fail "measure A B (text): expected a clean stderr"
elif ! grep -Eq '^rho_d .*[0-9] units³' "$tmp/stdout" || ! grep -q '^overlap area:' "$tmp/stdout" ||
     ! grep -q '^volume above:' "$tmp/stdout" || ! grep -q '^time total:' "$tmp/stdout"; then
  fail "measure A B (text): expected rho_d with units³, the overlap area, volumes and timings"
fi

# --- exact identities --------------------------------------------------------

if measure_json aa "$a" "$a"; then
  check "measure A A: zero gap" "
aa = r('aa')
assert aa['rho_d'] == 0 and aa['rho_d_axial'] == 0 and aa['rho_s'] == 1, aa
assert aa['signed_volume'] == 0 and aa['volume_above'] == 0 and aa['volume_below'] == 0, aa
assert aa['mean_abs_dz'] == 0 and close(aa['overlap_area'], 860 * 600, 1e-12), aa
"
fi

# threads: one thread and eight give the same bits (the stages' fixed halves).
if measure_json one_thread "$a" "$b" --threads=1 && measure_json eight_threads "$a" "$b" --threads=8; then
  check "--threads=1 and --threads=8: the same numbers" "
one, eight = r('one_thread'), r('eight_threads')
for key in ('rho_d', 'rho_d_axial', 'signed_volume', 'overlap_area', 'n_overlap_nodes', 'n_cells'):
    assert one[key] == eight[key], (key, one[key], eight[key])
"
fi

if measure_json ba "$b" "$a"; then
  check "measure B A = measure A B with above and below swapped" "
ab, ba = r('ab'), r('ba')
assert close(ab['rho_d'], ba['rho_d'], 1e-9), (ab['rho_d'], ba['rho_d'])
assert close(ab['volume_above'], ba['volume_below'], 1e-9), (ab['volume_above'], ba['volume_below'])
assert close(ab['volume_below'], ba['volume_above'], 1e-9), (ab['volume_below'], ba['volume_above'])
assert close(ab['overlap_area'], ba['overlap_area'], 1e-9), (ab['overlap_area'], ba['overlap_area'])
assert ab['n_overlap_nodes'] == ba['n_overlap_nodes'], (ab['n_overlap_nodes'], ba['n_overlap_nodes'])
"
fi

if measure_json up "$a" "$tmp/a_up.xyz"; then
  check "measure A (A + 1.5 m): the gap is 1.5 m everywhere" "
up = r('up')
area = up['overlap_area']
assert close(area, 860 * 600, 1e-12), up
assert close(up['rho_d'], 1.5 * area, 1e-9), up
assert close(up['signed_volume'], 1.5 * area, 1e-9), up
assert close(up['volume_above'], 1.5 * area, 1e-9), up
assert up['volume_below'] == 0, up
assert close(up['mean_abs_dz'], 1.5, 1e-9) and close(up['rho_d_axial'], 1.5, 1e-9), up
"
fi

# --- volume and weight modes -------------------------------------------------

if measure_json hull "$a" "$b" --domain=hull; then
  check "--domain=hull: overlap = B's hull" "
ab, h = r('ab'), r('hull')
hull_b = hull_area('$b')
assert h['domain'] == 'hull', h
assert close(h['overlap_area'], hull_b, 1e-9), (h['overlap_area'], hull_b)
assert close(h['domain_area_b'], hull_b, 1e-9) and h['excluded_area_b'] == 0, h
assert h['overlap_area'] > ab['overlap_area'] and h['n_overlap_nodes'] >= ab['n_overlap_nodes'], h
"
fi

# Over the data domain the union's triangles are kept where their centroid
# is in Ω: an area close to the overlay's, not the same.
if measure_json union "$a" "$b" --volume=union; then
  check "--volume=union: close to overlay on the pair" "
ab, un = r('ab'), r('union')
print('  union rho_d %.6f m³ vs overlay %.6f m³' % (un['rho_d'], ab['rho_d']))
assert un['volume_mode'] == 'union', un
assert close(un['rho_d'], ab['rho_d'], 0.10), (un['rho_d'], ab['rho_d'])
assert close(un['overlap_area'], ab['overlap_area'], 1e-3), (un['overlap_area'], ab['overlap_area'])
"
fi

if measure_json union_hull "$a" "$b" --volume=union --domain=hull; then
  check "--volume=union --domain=hull: the union's hull is B's" "
h, un = r('hull'), r('union_hull')
assert close(un['overlap_area'], h['overlap_area'], 1e-9), (un['overlap_area'], h['overlap_area'])
"
fi

if measure_json west "$a" "$a" --weights=mask:"$tmp/west.txt"; then
  check "--weights=mask: A A, west half (edges on the hull)" "
w = r('west')
assert w['weight_mode'] == 'mask' and close(w['overlap_area'], 860 * 600, 1e-12), w
assert close(w['weight_integral'], 430 * 600, 1e-6), w['weight_integral']
assert w['rho_d'] == 0, w
"
fi

# Over the hulls: the rectangle is inside B's hull, while B's data domain may
# leave out a triangle or two inside it (an empty spot of the random samples).
if measure_json inner "$a" "$b" --weights=mask:"$tmp/inner.txt" --domain=hull; then
  check "--weights=mask: A B, a rectangle inside B's hull" "
assert all(inside_hull('$b', x, y) for x, y in ((20, 20), (430, 20), (430, 580), (20, 580)))
w, ab = r('inner'), r('hull')
print('  mask weight_integral %.9f m² (rectangle %d m²), rho_d %.6f m³' % (w['weight_integral'], 410 * 560, w['rho_d']))
assert close(w['weight_integral'], 410 * 560, 1e-6), w['weight_integral']
assert close(w['overlap_area'], ab['overlap_area'], 1e-12), w
assert 0 < w['rho_d'] < ab['rho_d'], (w['rho_d'], ab['rho_d'])
assert close(w['mean_abs_dz'], w['rho_d'] / w['weight_integral'], 1e-9), w
"
fi

if has_part gdal; then  # rasters and CRSs: not in a build without GDAL
# --- lon/lat DEMs: one metric frame, areas in m², cut/fill -------------------

# Two ESRI ASCII grids with a .prj (GDAL reads the CRS from it): 40 x 30
# cells of 0.001 deg near Auckland (UTM zone 60S, about 200 km west of its
# central meridian), B = A + 5 m; the truths are computed here, not by
# surfreg: the ellipsoidal area of the lon/lat rectangle spanned by the
# cell centres (closed form on WGS 84, checked against a quadrature of
# M N cos(lat)), and UTM's point scale k at its centre (series in the
# longitude difference), since UTM areas are the ellipsoid's times k²;
# ENU places each sample by its height, so its areas are those at the
# data's height h, the ellipsoid's times (1 + h / R)².
python3 - "$tmp" <<'EOF' || { echo "FAIL: cannot make the lon/lat test inputs"; exit 1; }
import json, math, sys
tmp = sys.argv[1]
ncols, nrows, cell, west, south = 40, 30, 0.001, 174.75, -36.88
wgs84 = ('GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,'
         '298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]]')
utm60s = ('PROJCS["WGS_1984_UTM_Zone_60S",GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",'
          'SPHEROID["WGS_1984",6378137.0,298.257223563]],PRIMEM["Greenwich",0.0],'
          'UNIT["Degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],'
          'PARAMETER["False_Easting",500000.0],PARAMETER["False_Northing",10000000.0],'
          'PARAMETER["Central_Meridian",177.0],PARAMETER["Scale_Factor",0.9996],'
          'PARAMETER["Latitude_Of_Origin",0.0],UNIT["Meter",1.0]]')
def grid(name, prj, xll, yll, size, dz, columns=ncols):
    with open(f"{tmp}/{name}.asc", "w") as f:
        f.write(f"ncols {columns}\nnrows {nrows}\nxllcorner {xll!r}\nyllcorner {yll!r}\n"
                f"cellsize {size!r}\nNODATA_value -9999\n")
        for r in range(nrows):  # heights in quarter metres: exact in any float
            f.write(" ".join(repr(100 + ((r * 7 + c * 3) % 11) * 0.25 + dz)
                             for c in range(columns)) + "\n")
    with open(f"{tmp}/{name}.prj", "w") as f:
        f.write(prj)
for name, dz in (("ll_a", 0), ("ll_b", 5), ("ll_up2", 2), ("ll_down", -0.5)):
    grid(name, wgs84, west, south, cell, dz)
grid("utm_b", utm60s, 300000.0, 5915000.0, 90.0, 5)  # the same place, in UTM
# The same samples as a point file with no CRS (lon lat h): for --*_crs.
with open(f"{tmp}/ll_b.xyz", "w") as f:
    for r in range(nrows):
        for c in range(ncols):
            f.write(f"{west + (c + 0.5) * cell!r} {south + (nrows - r - 0.5) * cell!r} "
                    f"{100 + ((r * 7 + c * 3) % 11) * 0.25 + 5!r}\n")

a, f = 6378137.0, 1 / 298.257223563
e2 = f * (2 - f)
e, b2 = math.sqrt(e2), (a * (1 - f)) ** 2
def zone(lat):  # area from the equator to lat, per radian of longitude
    s = math.sin(math.radians(lat))
    return b2 * (s / (2 * (1 - e2 * s * s)) + math.log((1 + e * s) / (1 - e * s)) / (4 * e))
def area(lon0, lon1, lat0, lat1):
    return math.radians(lon1 - lon0) * (zone(lat1) - zone(lat0))
def area_by_quadrature(lon0, lon1, lat0, lat1, n=2000):  # Simpson on M N cos(lat)
    def g(lat):
        s = math.sin(math.radians(lat))
        w = 1 - e2 * s * s
        return a * (1 - e2) / w ** 1.5 * a / math.sqrt(w) * math.cos(math.radians(lat))
    h = (lat1 - lat0) / n
    total = g(lat0) + g(lat1) + sum((4 if i % 2 else 2) * g(lat0 + i * h) for i in range(1, n))
    return math.radians(lon1 - lon0) * math.radians(h) / 3 * total
lon0, lon1 = west + 0.5 * cell, west + (ncols - 0.5) * cell  # first and last cell centres
lat0, lat1 = south + 0.5 * cell, south + (nrows - 0.5) * cell
whole = area(lon0, lon1, lat0, lat1)
assert abs(area_by_quadrature(lon0, lon1, lat0, lat1) / whole - 1) < 1e-12
mid = west + 20 * cell  # the mask's east edge: halfway between centres 19 and 20
lat_c, dlon = math.radians((lat0 + lat1) / 2), math.radians((lon0 + lon1) / 2 - 177.0)
c2 = math.cos(lat_c) ** 2
k = 0.9996 * (1 + c2 * dlon ** 2 * (1 + e2 / (1 - e2) * c2) / 2)
w = 1 - e2 * math.sin(lat_c) ** 2
radius = a * math.sqrt(1 - e2) / w  # Gaussian radius sqrt(M N)
height = sum(100 + ((r * 7 + c * 3) % 11) * 0.25 for r in range(nrows) for c in range(ncols)) / (nrows * ncols)
with open(f"{tmp}/geo.json", "w") as out:
    json.dump({"area": whole, "west_area": area(lon0, mid, lat0, lat1),
               "window_area": area(lon0, west + 19.5 * cell, lat0, lat1), "k2": k * k,
               "height_scale": (1 + height / radius) ** 2,
               "lat_centre": (lat0 + lat1) / 2, "lon_centre": (lon0 + lon1) / 2}, out)
with open(f"{tmp}/ll_west.txt", "w") as out:  # lon lat: the west half, edges beyond the data
    out.write(f"{west - 0.01!r} {south - 0.01!r}\n{mid!r} {south - 0.01!r}\n"
              f"{mid!r} {south + 0.04!r}\n{west - 0.01!r} {south + 0.04!r}\n")
EOF

if measure_json ll "$tmp/ll_a.asc" "$tmp/ll_b.asc"; then
  check "lon/lat DEM against itself + 5 m: UTM frame, area in m² of the ellipsoid's" "
m, g = r('ll'), r('geo')
print('  overlap %.3f m², ellipsoid %.3f m² (%+.4f%%), ellipsoid x k² %.3f m² (%+.2e)' % (
    m['overlap_area'], g['area'], 100 * (m['overlap_area'] / g['area'] - 1),
    g['area'] * g['k2'], m['overlap_area'] / (g['area'] * g['k2']) - 1))
assert m['frame'] == 'UTM zone 60S (WGS 84; EPSG:32760)', m['frame']
assert m['crs_a'] == m['crs_b'] == 'WGS 84 (EPSG:4326)', (m['crs_a'], m['crs_b'])
assert m['length_unit'] == 'm', m
assert abs(m['overlap_area'] / g['area'] - 1) < 1e-3, (m['overlap_area'], g['area'])
assert abs(m['overlap_area'] / (g['area'] * g['k2']) - 1) < 2e-5, (m['overlap_area'], g)
assert abs(m['mean_abs_dz'] - 5) < 1e-9 and abs(m['rho_d_axial'] - 5) < 1e-9, m
assert close(m['rho_d'], 5 * m['overlap_area'], 1e-9) and m['volume_below'] == 0, m
c = m['change']
assert c['level_of_detection'] == 0 and close(c['fill'], m['volume_above'], 1e-9), c
"
fi

run measure "$tmp/ll_a.asc" "$tmp/ll_b.asc"
if [[ $rc -ne 0 ]] || ! grep -q '^frame: *UTM zone 60S (WGS 84; EPSG:32760)$' "$tmp/stdout" ||
   ! grep -Eq '^overlap area: *[0-9.e+]+ m² ' "$tmp/stdout" ||
   ! grep -Eq '^rho_d .* m³ ' "$tmp/stdout" || ! grep -Eq '^fill: .* m³ ' "$tmp/stdout" ||
   ! grep -q 'CRS WGS 84 (EPSG:4326))$' "$tmp/stdout" || grep -q 'units' "$tmp/stdout"; then
  fail "measure lon/lat (text): expected the frame, the CRSs, m² and m³, no 'units'"
fi

if measure_json ll_enu "$tmp/ll_a.asc" "$tmp/ll_b.asc" --frame=enu; then
  check "--frame=enu: areas at the data's height, the origin at full precision" "
m, g = r('ll_enu'), r('geo')
at_height = g['area'] * g['height_scale']
print('  ENU overlap %.3f m² (%+.2e of the ellipsoid\'s, %+.2e of it at the mean height)' % (
    m['overlap_area'], m['overlap_area'] / g['area'] - 1, m['overlap_area'] / at_height - 1))
assert abs(m['overlap_area'] / at_height - 1) < 2e-6, (m['overlap_area'], at_height)
assert abs(m['mean_abs_dz'] - 5) < 1e-6, m
lat, lon = m['frame'].split('local ENU about ')[1].split(', h 0 m')[0].split()
assert lat[-1] == 'S' and lon[-1] == 'E', m['frame']
assert abs(-float(lat[:-1]) - g['lat_centre']) < 1e-12 and abs(float(lon[:-1]) - g['lon_centre']) < 1e-12, (m['frame'], g)
assert '+proj=topocentric +ellps=WGS84 +lat_0=-%s +lon_0=%s +h_0=0)' % (lat[:-1], lon[:-1]) in m['frame'], m['frame']
"
fi

# A lon/lat mask polygon follows A into the frame; a window of A; a point
# file given its CRS by flag.
if measure_json ll_mask "$tmp/ll_a.asc" "$tmp/ll_b.asc" --weights=mask:"$tmp/ll_west.txt" &&
   measure_json ll_window "$tmp/ll_a.asc" "$tmp/ll_b.asc" --window=0,0,20,0 &&
   measure_json ll_xyz "$tmp/ll_a.asc" "$tmp/ll_b.xyz" --moving_crs=EPSG:4326; then
  check "mask (lon/lat polygon), --window, --moving_crs on a point file" "
g, k2 = r('geo'), r('geo')['k2']
w = r('ll_mask')
assert abs(w['weight_integral'] / (g['west_area'] * k2) - 1) < 2e-5, (w['weight_integral'], g['west_area'] * k2)
assert close(w['rho_d'], 5 * w['weight_integral'], 1e-9), w
v = r('ll_window')
assert v['n_points_a'] == 20 * 30 and abs(v['overlap_area'] / (g['window_area'] * k2) - 1) < 2e-5, v
x = r('ll_xyz')
assert x['frame'] == r('ll')['frame'] and x['crs_b'] == 'WGS 84 (EPSG:4326)', x
# B's own Delaunay diagonals, not A's cell split: 5 m at the nodes, near 5 between.
assert abs(x['rho_d_axial'] - 5) < 1e-9 and abs(x['mean_abs_dz'] - 5) < 0.01, x
assert abs(x['overlap_area'] / (g['area'] * k2) - 1) < 2e-5, x
"
fi

# Cut/fill beyond a level of detection, against hand-computed figures: a
# uniform +2 m (all fill), a uniform -0.5 m under L = 1 (no change), and
# on a no-CRS square a gap linear in x (dz = x - 5 on [0, 10]², exact on
# any triangulation): fill = cut = ∫_6^10 (x - 5) dx · 10 = 120 over 40.
python3 - "$tmp" <<'EOF'
import sys
with open(sys.argv[1] + "/flat.xyz", "w") as a, open(sys.argv[1] + "/ramp.xyz", "w") as b:
    for i in range(11):
        for j in range(11):
            a.write(f"{i} {j} 0\n")
            b.write(f"{i} {j} {i - 5}\n")
EOF
if measure_json lod2 "$tmp/ll_a.asc" "$tmp/ll_up2.asc" --lod=1 &&
   measure_json lod_none "$tmp/ll_a.asc" "$tmp/ll_down.asc" --lod=1 &&
   measure_json ramp "$tmp/flat.xyz" "$tmp/ramp.xyz" --lod=1; then
  check "--lod: change keys against hand-computed cut/fill" "
m, g = r('lod2'), r('geo')
c, area = m['change'], m['overlap_area']
keys = ['level_of_detection', 'fill', 'cut', 'net', 'fill_area', 'cut_area', 'fill_uncertainty',
        'cut_uncertainty', 'net_uncertainty']
assert sorted(c) == sorted(keys), c
assert abs(area / (g['area'] * g['k2']) - 1) < 2e-5, area
assert c['level_of_detection'] == 1 and close(c['fill'], 2 * area, 1e-9) and c['cut'] == 0, c
assert close(c['net'], 2 * area, 1e-9) and close(c['fill_area'], area, 1e-9) and c['cut_area'] == 0, c
assert close(c['fill_uncertainty'], area, 1e-9) and c['cut_uncertainty'] == 0, c
assert close(c['net_uncertainty'], area, 1e-9), c
n = r('lod_none')['change']
assert n['fill'] == n['cut'] == n['net'] == n['fill_area'] == n['cut_area'] == 0, n
assert r('lod_none')['volume_below'] > 0, r('lod_none')
p = r('ramp')
c = p['change']
print('  ramp: fill %.12g cut %.12g over %.12g / %.12g %s²' % (c['fill'], c['cut'], c['fill_area'], c['cut_area'], p['length_unit']))
assert p['length_unit'] == 'units' and p['frame'] == 'coordinates as given (no CRS)', p
assert abs(c['fill'] - 120) < 1e-9 and abs(c['cut'] - 120) < 1e-9 and abs(c['net']) < 1e-9, c
assert abs(c['fill_area'] - 40) < 1e-9 and abs(c['cut_area'] - 40) < 1e-9, c
assert abs(c['fill_uncertainty'] - 40) < 1e-9 and abs(c['net_uncertainty'] - 80) < 1e-9, c
assert abs(p['volume_above'] - 125) < 1e-9, p  # ∫_5^10 (x - 5) dx · 10 at L = 0
"
fi
if measure_json ll_union "$tmp/ll_a.asc" "$tmp/ll_b.asc" --volume=union; then
  check "--volume=union: no change object (cut/fill is the overlay's)" "
assert 'change' not in r('ll_union'), r('ll_union')
"
fi

fi  # has_part gdal

# --- progress: from the start for 200,000 samples or 5 MB of input or more, none with --quiet ---
python3 - "$tmp" <<'EOF' || { echo "FAIL: cannot make the progress inputs"; exit 1; }
import math, random, sys
random.seed(3)
for name, dz in (("big_a", 0.0), ("big_b", 0.1)):
    with open(f"{sys.argv[1]}/{name}.xyz", "w") as f:
        for _ in range(140000):
            x, y = random.uniform(0, 300), random.uniform(0, 300)
            f.write("%.4f %.4f %.4f\n" % (x, y, math.sin(x / 20) * math.cos(y / 30) + dz))
EOF
run measure "$tmp/big_a.xyz" "$tmp/big_b.xyz" --json
checks=$((checks + 1))
if [[ $rc -ne 0 ]] || ! grep -q "^measure: reading $tmp/big_a.xyz and $tmp/big_b.xyz ([0-9.]* MB)" "$tmp/stderr" ||
   ! grep -q "^measure: triangulating (5% done" "$tmp/stderr" ||
   ! grep -q "^measure: volume (60% done, [0-9.]* s, about [0-9.]* s left)" "$tmp/stderr" ||
   grep -q "^measure:" "$tmp/stdout"; then
  fail "measure of 2 x 140,000 samples (6.7 MB): expected the reading line and stage lines with the time left on stderr only"
fi
run measure "$tmp/big_a.xyz" "$tmp/big_b.xyz" --json --quiet
checks=$((checks + 1))
[[ $rc -eq 0 && ! -s "$tmp/stderr" ]] || fail "measure --quiet: expected no progress on stderr"

# --- bad input: exit 2, one line naming what is wrong ------------------------

expect_input_error "configs/data/no_such_b.xyz: cannot open" measure "$a" configs/data/no_such_b.xyz
expect_input_error "configs/data/no_such_a.xyz: cannot open" measure configs/data/no_such_a.xyz "$b"
expect_input_error "'--volume'" measure "$a" "$b" --volume=foo
expect_input_error "'--weights'" measure "$a" "$b" --weights=bogus
expect_input_error "flag '--domain' expects one of data, hull, got 'convex'" \
  measure "$a" "$b" --domain=convex
expect_input_error "flag '--domain_max_edge_spacings' expects a number in [1, 100], got '0.5'" \
  measure "$a" "$b" --domain_max_edge_spacings=0.5
expect_input_error "'--weights'" measure "$a" "$b" --weights=mask:
expect_input_error "$tmp/bad_line.txt:4: y is not a number: '6O0'" \
  measure "$a" "$b" --weights=mask:"$tmp/bad_line.txt"
expect_input_error "$tmp/three_numbers.txt:2:" \
  measure "$a" "$b" --weights=mask:"$tmp/three_numbers.txt"
expect_input_error "$tmp/two_vertices.txt: " \
  measure "$a" "$b" --weights=mask:"$tmp/two_vertices.txt"
expect_input_error "$tmp/no_such_mask.txt: cannot open" \
  measure "$a" "$b" --weights=mask:"$tmp/no_such_mask.txt"
expect_input_error "" measure "$a" "$tmp/b_far.xyz"
expect_input_error "" measure "$a" "$tmp/b_far.xyz" --json
if has_part gdal; then  # rasters and CRSs: not in a build without GDAL
# CRSs: a flag that disagrees with the raster's own, a CRS on one surface
# only, unreadable CRS and frame values; two DEMs in different CRSs measure.
expect_input_error "flag '--reference_crs': 'WGS 84 / UTM zone 60S' disagrees with the CRS of $tmp/ll_a.asc ('WGS 84')" \
  measure "$tmp/ll_a.asc" "$tmp/ll_b.asc" --reference_crs=EPSG:32760
expect_input_error "flag '--moving_crs': 'NAD27' disagrees with the CRS of $tmp/ll_b.asc ('WGS 84')" \
  measure "$tmp/ll_a.asc" "$tmp/ll_b.asc" --moving_crs=EPSG:4267
expect_input_error "and moving $tmp/ll_b.xyz (CRS none): the reference surface has a CRS and the moving has none; give it with the key 'moving_crs' (flag --moving_crs)" \
  measure "$tmp/ll_a.asc" "$tmp/ll_b.xyz"
# A moving DEM in another CRS is reprojected into the reference's (here
# UTM 60S into lon/lat), then both go into the metric frame; the JSON and
# the summary say so.
if measure_json utm_into_ll "$tmp/ll_a.asc" "$tmp/utm_b.asc"; then
  python3 - "$tmp/stdout" <<'PY' || fail "lon/lat against UTM: expected the UTM 60S frame and an overlap"
import json, sys
j = json.load(open(sys.argv[1]))
print("lon/lat against UTM: frame %s, overlap %.0f m2, B reprojected from %s" % (
    j["frame"], j["overlap_area"], j.get("b_reprojected_from")))
sys.exit(0 if j["frame"].startswith("UTM zone 60S") and j["overlap_area"] > 1e6
         and j.get("b_reprojected_from") == "WGS 84 / UTM zone 60S" else 1)
PY
fi
run measure "$tmp/ll_a.asc" "$tmp/utm_b.asc"
grep -q "^reprojected: *B from WGS 84 / UTM zone 60S into A's WGS 84$" "$tmp/stdout" ||
  fail "lon/lat against UTM: the summary does not say that B was reprojected"
expect_input_error "flag '--reference_crs': unreadable CRS 'EPSG:999999'" \
  measure "$tmp/ll_a.asc" "$tmp/ll_b.asc" --reference_crs=EPSG:999999
expect_input_error "flag '--frame' expects one of auto, enu, utm, got 'mercator'" \
  measure "$tmp/ll_a.asc" "$tmp/ll_b.asc" --frame=mercator
fi  # has_part gdal
expect_input_error "flag '--lod' expects" measure "$a" "$b" --lod=-1
expect_input_error "flag '--lod': cut/fill beyond a level of detection needs --volume=overlay" \
  measure "$a" "$b" --lod=1 --volume=union
has_part gdal &&
  expect_input_error "argument A: $tmp/ll_a.asc: band 2 of 1" measure "$tmp/ll_a.asc" "$tmp/ll_b.asc" --band=2

# --- bad usage -----------------------------------------------------------------

expect_usage_error measure "$a"
expect_usage_error measure
expect_usage_error measure "$a" "$b" "$b"
run help measure
if [[ $rc -ne 0 ]] || ! grep -q 'usage: surfreg measure A B' "$tmp/stdout"; then
  fail "help measure: expected the measure usage line"
fi

echo "$((checks - failures)) of $checks checks passed"
[[ $failures -eq 0 ]]

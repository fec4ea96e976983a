#!/usr/bin/env bash
# End-to-end tests of LAS input and text-cloud columns through `surfreg
# measure` and `align`: a LAS file made here (python3, standard library) from
# the sample pair's points gives exactly the measures of the same points as
# .xyz, `--classes` keeps the points of those classes only, `--columns`
# picks x, y, z from a wider text file, and LAZ, a truncated LAS and classes
# on a text cloud are exit 2 with one line.
# Usage: cli_las_test.sh SURFREG_BINARY
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
failures=0
checks=0

# From volcano_a.xyz: a.las (format 1, LAS 1.2, scale 0.001, a UTM-like
# offset, every 5th point class 7 and 40 m higher: "noise"), the same points
# as a.xyz (x y z as Python prints X * scale + offset: the same doubles the
# reader computes), ground.xyz (the class-2 points only), wide.csv (the
# points with 4 more columns, ';'-separated, a header), a14.las (LAS 1.4,
# format 6, 5 extra bytes per record, 64-bit count); and cut.las, a.las
# less its last 10 bytes.
python3 - "$tmp" <<'EOF'
import struct, sys
out = sys.argv[1]
points = []
for line in open("configs/data/volcano_a.xyz"):
    line = line.split("#")[0].split()
    if line:
        points.append(tuple(float(v) for v in line))
scale, offset = (0.001, 0.001, 0.001), (600000.0, 5900000.0, 0.0)
records = []
for i, (x, y, z) in enumerate(points):
    cls = 7 if i % 5 == 0 else 2
    if cls == 7:
        z += 40
    xyz = [round((v - o) / s) for v, o, s in zip((x + 600000.0, y + 5900000.0, z), offset, scale)]
    records.append((xyz, cls))
def coords(xyz):
    return [v * s + o for v, s, o in zip(xyz, scale, offset)]
def las(minor, fmt, length, name, epsg=0):
    header_size = 375 if minor == 4 else 227
    vlr = b""
    if epsg:  # GeoKeyDirectory: ProjectedCSTypeGeoKey (3072) = epsg
        keys = struct.pack("<8H", 1, 1, 0, 1, 3072, 0, 1, epsg)
        vlr = struct.pack("<H16sHH32s", 0, b"LASF_Projection", 34735, len(keys), b"") + keys
    h = bytearray(header_size)
    h[0:4] = b"LASF"
    h[24], h[25] = 1, minor
    struct.pack_into("<HIIBHI", h, 94, header_size, header_size + len(vlr), 1 if vlr else 0, fmt,
                     length, len(records) if fmt < 6 else 0)
    struct.pack_into("<6d", h, 131, *scale, *offset)
    if minor == 4:
        struct.pack_into("<Q", h, 247, len(records))
    body = bytearray()
    for xyz, cls in records:
        r = bytearray(length)
        struct.pack_into("<3i", r, 0, *xyz)
        if fmt < 6:
            r[15] = cls
        else:
            r[16] = cls
        body += r
    with open(f"{out}/{name}", "wb") as f:
        f.write(h + vlr + body)
    return bytes(h + vlr + body)
data = las(2, 1, 28, "a.las")
las(4, 6, 35, "a14.las")
las(2, 1, 28, "nztm.las", epsg=2193)
open(f"{out}/cut.las", "wb").write(data[:-10])
with open(f"{out}/a.xyz", "w") as a, open(f"{out}/ground.xyz", "w") as g, \
        open(f"{out}/wide.csv", "w") as w:
    w.write("id;X;Y;Z;intensity;class\n")
    for i, (xyz, cls) in enumerate(records):
        text = " ".join(repr(v) for v in coords(xyz))
        a.write(text + "\n")
        if cls == 2:
            g.write(text + "\n")
        x, y, z = (repr(v) for v in coords(xyz))
        w.write(f"{i};{x};{y};{z};{100 + i % 50};{cls}\n")
EOF
# B: volcano_b.xyz in the same offset frame.
awk '!/^#/ && NF { printf "%.17g %.17g %s\n", $1 + 600000, $2 + 5900000, $3 }' \
  configs/data/volcano_b.xyz >"$tmp/b.xyz"

# measures NAME ARGS...: `surfreg measure ARGS... --json`, exit 0; the
# measures (no file names or timings) saved as $tmp/NAME.txt.
measures() {
  local name=$1
  shift
  run measure "$@" --json
  if [[ $rc -ne 0 ]]; then
    fail "measure $*: expected exit 0"
    return 1
  fi
  python3 -c '
import json, sys
r = json.loads(sys.stdin.read())
for key in ("file_a", "file_b", "timings"):
    r.pop(key, None)
print(json.dumps(r, sort_keys=True))
' <"$tmp/stdout" >"$tmp/$name.txt"
}

same() {
  checks=$((checks + 1))
  if ! cmp -s "$tmp/$1.txt" "$tmp/$2.txt"; then
    fail "$1 and $2 measures differ: $(diff "$tmp/$1.txt" "$tmp/$2.txt" | head -c 600)"
  fi
}

measures las "$tmp/a.las" "$tmp/b.xyz"
measures xyz "$tmp/a.xyz" "$tmp/b.xyz"
same las xyz
measures las14 "$tmp/a14.las" "$tmp/b.xyz"
same las14 xyz
measures ground_las "$tmp/a.las" "$tmp/b.xyz" --classes=2
measures ground_xyz "$tmp/ground.xyz" "$tmp/b.xyz"
same ground_las ground_xyz
checks=$((checks + 1))
cmp -s "$tmp/las.txt" "$tmp/ground_las.txt" && fail "--classes=2 changed nothing"
# `columns` is for both text inputs: B in the same layout.
awk 'BEGIN { print "id;X;Y;Z;intensity;class" } { print NR ";" $1 ";" $2 ";" $3 ";7;2" }' \
  "$tmp/b.xyz" >"$tmp/b_wide.csv"
measures wide "$tmp/wide.csv" "$tmp/b_wide.csv" --columns=X,Y,Z
same wide xyz
measures wide_positions "$tmp/wide.csv" "$tmp/b_wide.csv" --columns=2,3,4
same wide_positions xyz
# A LAS file and a text cloud: `columns` is the text cloud's.
measures las_wide "$tmp/a.las" "$tmp/b_wide.csv" --columns=x,y,z
same las_wide xyz

# A LAS against itself with classes 2 and 7: everything, rho_d 0.
run measure "$tmp/a.las" "$tmp/a14.las" --classes=2,7 --json
checks=$((checks + 1))
python3 -c 'import json,sys; r = json.load(sys.stdin); sys.exit(r["rho_d"] != 0)' \
  <"$tmp/stdout" || fail "a.las against a14.las: expected rho_d 0"

if has_part gdal; then  # rasters and CRSs: not in a build without GDAL
# The CRS of the GeoTIFF keys: named in the JSON, measured as given (the
# same measures), and a CRS on one input only is refused as for rasters.
measures nztm "$tmp/nztm.las" "$tmp/b.xyz" --moving_crs=EPSG:2193
checks=$((checks + 1))
grep -q '"crs_a": "NZGD2000 / New Zealand Transverse Mercator 2000 (EPSG:2193)"' "$tmp/nztm.txt" ||
  fail "nztm.las: expected crs_a EPSG:2193 in $(cat "$tmp/nztm.txt" | head -c 300)"
python3 - "$tmp/nztm.txt" "$tmp/xyz.txt" <<'EOF2' || fail "nztm.las: measures differ from the xyz's"
import json, sys
a, b = (json.loads(open(p).read()) for p in sys.argv[1:])
for key in ("rho_d", "rho_d_axial", "overlap_area", "n_points_a", "n_points_b"):
    assert a[key] == b[key], (key, a[key], b[key])
EOF2
fi  # has_part gdal
# align: the LAS pair of the same points as the text pair, the same motion.
run align "$tmp/a.las" "$tmp/a14.las" --classes=2 --free=translation --json
checks=$((checks + 1))
if [[ $rc -ne 0 ]] || ! python3 -c '
import json, sys
r = json.load(sys.stdin)
sys.exit(max(abs(v) for v in r["translation"]) > 1e-6)' <"$tmp/stdout"; then
  fail "align a.las a14.las --classes=2: expected exit 0 and no shift"
fi

# expect_error EXPECTED ARGS...: exit 2 and exactly one stderr line with EXPECTED.
expect_error() {
  local expected=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "$*: expected exit 2"
  elif [[ $(wc -l <"$tmp/stderr") -ne 1 ]] || ! grep -qF -- "$expected" "$tmp/stderr"; then
    fail "$*: expected one line with: $expected"
  fi
}

has_part gdal &&
  expect_error "give it with the key 'moving_crs'" measure "$tmp/nztm.las" "$tmp/b.xyz"

cp "$tmp/a.las" "$tmp/x.laz"
expect_error "x.laz: LAZ (compressed LAS) is not supported: decompress it first, e.g. \`laszip -i x.laz -o x.las\` or \`pdal translate x.laz x.las\`" \
  measure "$tmp/x.laz" "$tmp/b.xyz"
expect_error "cut.las: the header declares 5307 points of 28 bytes from byte 227, but the file has" \
  measure "$tmp/cut.las" "$tmp/b.xyz"
expect_error "a.xyz: \`classes\` keeps LAS classifications, but a .xyz file has no classes (flag '--classes')" \
  measure "$tmp/a.xyz" "$tmp/b.xyz" --classes=2 --json
expect_error "found 6 columns; give \`columns\` (e.g. columns: 1,2,3) to pick x, y, z" \
  measure "$tmp/wide.csv" "$tmp/b.xyz"
expect_error "flag '--classes' expects a list of LAS classifications" \
  align "$tmp/a.las" "$tmp/a14.las" --classes=ground
expect_error "none of its 5307 points has classification 9 (key 'classes')" \
  align "$tmp/a.las" "$tmp/a14.las" --classes=9

echo "$checks checks, $failures failures"
[[ $failures -eq 0 ]]

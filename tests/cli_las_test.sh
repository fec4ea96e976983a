#!/usr/bin/env bash
# End-to-end tests of LAS input and text-cloud columns through `surfreg
# measure` and `align`: a LAS file made here (python3, standard library) from
# the sample pair's points gives exactly the measures of the same points as
# .xyz, `--classes` keeps the points of those classes only, `--columns`
# picks x, y, z from a wider text file, `transform` and `align --aligned`
# write LAS (a LAS input's records moved, attributes kept), and LAZ, a
# truncated LAS and classes on a text cloud are exit 2 with one line.
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

# LAS output. T: 1 degree about z and a shift, as a 4 x 4 text matrix.
python3 - "$tmp/t.txt" <<'EOF2'
import math, sys
c, s = math.cos(math.radians(1)), math.sin(math.radians(1))
rows = [[c, -s, 0, 12.5], [s, c, 0, -7.25], [0, 0, 1, 3.0], [0, 0, 0, 1]]
open(sys.argv[1], "w").write("".join(" ".join(repr(float(v)) for v in r) + "\n" for r in rows))
EOF2
# las_check.py A.las B.las MODE: compares two LAS files record by record.
# same-bytes: every byte but x, y, z alike and the coordinates within one
# scale step; moved-by T.txt: B's coordinates are A's moved by T.
cat >"$tmp/las_check.py" <<'EOF2'
import struct, sys
def read(path):
    d = open(path, "rb").read()
    minor, = struct.unpack_from("<B", d, 25)
    at, = struct.unpack_from("<I", d, 96)
    length, = struct.unpack_from("<H", d, 105)
    count, = struct.unpack_from("<I", d, 107)
    if minor >= 4 and count == 0:
        count, = struct.unpack_from("<Q", d, 247)
    scale = struct.unpack_from("<3d", d, 131)
    offset = struct.unpack_from("<3d", d, 155)
    bounds = struct.unpack_from("<6d", d, 179)
    recs = []
    for i in range(count):
        r = d[at + i * length: at + (i + 1) * length]
        xyz = [v * s + o for v, s, o in zip(struct.unpack_from("<3i", r, 0), scale, offset)]
        recs.append((xyz, r[12:]))
    return d[:at], recs, scale, bounds
a_head, a, a_scale, _ = read(sys.argv[1])
b_head, b, b_scale, b_bounds = read(sys.argv[2])
assert len(a) == len(b), (len(a), len(b))
assert all(ra[1] == rb[1] for ra, rb in zip(a, b)), "attributes differ"
assert a_head[227:] == b_head[227:], "VLRs differ"
step = max(max(a_scale), max(b_scale))
if sys.argv[3] == "same":
    worst = max(abs(p - q) for ra, rb in zip(a, b) for p, q in zip(ra[0], rb[0]))
else:
    m = [[float(v) for v in line.split()] for line in open(sys.argv[3]) if line.strip()]
    worst = max(abs(sum(m[i][k] * ra[0][k] for k in range(3)) + m[i][3] - rb[0][i])
                for ra, rb in zip(a, b) for i in range(3))
assert worst <= step, (worst, step)
lo = [min(r[0][k] for r in b) for k in range(3)]
hi = [max(r[0][k] for r in b) for k in range(3)]
assert all(abs(b_bounds[2 * k] - hi[k]) <= step and abs(b_bounds[2 * k + 1] - lo[k]) <= step for k in range(3)), "bounds"
EOF2
run transform "$tmp/a.las" --transform="$tmp/t.txt" --output="$tmp/moved.las"
checks=$((checks + 1))
[[ $rc -eq 0 ]] && python3 "$tmp/las_check.py" "$tmp/a.las" "$tmp/moved.las" "$tmp/t.txt" ||
  fail "transform a.las -> moved.las: expected every record moved by T, attributes and VLRs kept"
run transform "$tmp/moved.las" --transform="$tmp/t.txt" --inverse --output="$tmp/back.las"
checks=$((checks + 1))
[[ $rc -eq 0 ]] && python3 "$tmp/las_check.py" "$tmp/a.las" "$tmp/back.las" same ||
  fail "transform --inverse: expected a.las back within one scale step"
run transform "$tmp/a14.las" --transform="$tmp/t.txt" --output="$tmp/moved14.las"
checks=$((checks + 1))
[[ $rc -eq 0 ]] && python3 "$tmp/las_check.py" "$tmp/a14.las" "$tmp/moved14.las" "$tmp/t.txt" ||
  fail "transform a14.las (LAS 1.4, format 6, extra bytes): expected every record moved by T"
# A text cloud written as LAS: the points of the .xyz output to 1e-9 of the
# extent (the mean gap at the nodes; the volume is not compared: on this
# grid the quantization flips Delaunay diagonals of co-circular cells).
run transform "$tmp/a.xyz" --transform="$tmp/t.txt" --output="$tmp/fresh.las"
run transform "$tmp/a.xyz" --transform="$tmp/t.txt" --output="$tmp/fresh.xyz"
run measure "$tmp/fresh.las" "$tmp/fresh.xyz" --json
checks=$((checks + 1))
python3 -c 'import json,sys; r = json.load(sys.stdin); sys.exit(not (r["rho_d_axial"] < 1e-5 and r["n_points_a"] == 5307))' \
  <"$tmp/stdout" || fail "fresh.las: expected the points of fresh.xyz"
# align --aligned=X.las from a LAS moving file: all its records (class 7
# too) moved by the matrix, attributes kept.
run align "$tmp/b.xyz" "$tmp/a.las" --classes=2 --aligned="$tmp/aligned.las" --matrix_txt="$tmp/m.txt"
checks=$((checks + 1))
[[ $rc -eq 0 ]] && python3 "$tmp/las_check.py" "$tmp/a.las" "$tmp/aligned.las" "$tmp/m.txt" ||
  fail "align --aligned=aligned.las: expected a.las's records moved by the matrix"

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

#!/usr/bin/env bash
# Masks of several rings (issue 22) through `surfreg measure`, on the sample
# pair in configs/data over the hulls, where the mask's area is known
# exactly: text rings = the same rings as GeoJSON (read through OGR), an
# exclude mask = the full measure − the include one, a MultiPolygon = the sum
# of its parts; and each mask file error as one line (exit 2).
# Usage: cli_mask_test.sh SURFREG_BINARY   (needs python3, standard library;
# paths relative to the project root, this script's parent folder)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
source "$(dirname -- "$(realpath -- "$0")")/measure_harness.sh"  # measure_json, check, expect_input_error
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

measure_json hull "$a" "$b" --domain=hull || exit 1

# --- masks of several rings: text and GeoJSON (OGR), include and exclude ----

# The inner rectangle with a hole, as text rings and as a GeoJSON polygon
# (written here: OGR reads GeoJSON as it reads a GeoPackage); over the hulls
# the mask's area is known exactly.
printf '20 20\n430 20\n430 580\n20 580\n>\n100 100\n300 100\n300 300\n100 300\n' >"$tmp/holed.txt"
cat >"$tmp/holed.geojson" <<'JSON'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 7, "properties": {}, "geometry": {"type": "Polygon", "coordinates": [
   [[20, 20], [430, 20], [430, 580], [20, 580], [20, 20]],
   [[100, 100], [100, 300], [300, 300], [300, 100], [100, 100]]]}}]}
JSON
# Two parts (one with the hole) as a MultiPolygon, and each part alone.
cat >"$tmp/parts.geojson" <<'JSON'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 1, "properties": {}, "geometry": {"type": "MultiPolygon", "coordinates": [
   [[[20, 20], [430, 20], [430, 580], [20, 580], [20, 20]],
    [[100, 100], [100, 300], [300, 300], [300, 100], [100, 100]]],
   [[[500, 100], [800, 150], [700, 500], [520, 400], [500, 100]]]]}}]}
JSON
printf '500 100\n800 150\n700 500\n520 400\n' >"$tmp/part2.txt"
if measure_json holed_txt "$a" "$b" --weights=mask:"$tmp/holed.txt" --domain=hull &&
   measure_json holed_json "$a" "$b" --weights=mask:"$tmp/holed.geojson" --domain=hull &&
   measure_json holed_out "$a" "$b" --weights=mask:"$tmp/holed.geojson" --mask_mode=exclude --domain=hull &&
   measure_json parts "$a" "$b" --weights=mask:"$tmp/parts.geojson" --domain=hull &&
   measure_json part2 "$a" "$b" --weights=mask:"$tmp/part2.txt" --domain=hull; then
  check "mask rings: a hole (text = GeoJSON), exclude = full - include, two parts = the sum" "
t, g, x, h = r('holed_txt'), r('holed_json'), r('holed_out'), r('hull')
assert close(t['weight_integral'], 410 * 560 - 200 * 200, 1e-9), t['weight_integral']
assert t['mask_rings'] == 2 and g['mask_rings'] == 2 and t['mask_vertices'] == 8, (t, g)
for key in ('rho_d', 'weight_integral', 'signed_volume', 'volume_above'):
    assert close(g[key], t[key], 1e-12), (key, g[key], t[key])
assert x['mask_mode'] == 'exclude', x
for key in ('rho_d', 'weight_integral', 'signed_volume'):
    assert close(x[key] + t[key], h[key], 1e-9), (key, x[key], t[key], h[key])
p, p2 = r('parts'), r('part2')
for key in ('rho_d', 'weight_integral', 'signed_volume'):
    assert close(p[key], t[key] + p2[key], 1e-9), (key, p[key], t[key], p2[key])
"
fi
# The same holed polygon as a GeoPackage (an SQLite file by the GeoPackage
# 1.3 tables, written with Python's sqlite3; no CRS: the reference's), as
# an exclude mask: the same measures as the text rings excluded.
python3 - "$tmp/holed.gpkg" <<'PY'
import sqlite3, struct, sys
db = sqlite3.connect(sys.argv[1])
db.execute("PRAGMA application_id = 1196444487")  # 'GPKG'
db.execute("PRAGMA user_version = 10300")
db.executescript("""
CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL, srs_id INTEGER PRIMARY KEY,
  organization TEXT NOT NULL, organization_coordsys_id INTEGER NOT NULL, definition TEXT NOT NULL,
  description TEXT);
INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined cartesian SRS', -1, 'NONE', -1, 'undefined', NULL);
INSERT INTO gpkg_spatial_ref_sys VALUES ('Undefined geographic SRS', 0, 'NONE', 0, 'undefined', NULL);
CREATE TABLE gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL,
  identifier TEXT UNIQUE, description TEXT DEFAULT '', last_change DATETIME NOT NULL DEFAULT
  (strftime('%Y-%m-%dT%H:%M:%fZ','now')), min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE,
  srs_id INTEGER);
CREATE TABLE gpkg_geometry_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL,
  geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL, z TINYINT NOT NULL, m TINYINT NOT NULL,
  CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name));
CREATE TABLE slides (fid INTEGER PRIMARY KEY AUTOINCREMENT, geom POLYGON);
INSERT INTO gpkg_contents (table_name, data_type, identifier, srs_id) VALUES ('slides', 'features', 'slides', -1);
INSERT INTO gpkg_geometry_columns VALUES ('slides', 'geom', 'POLYGON', -1, 0, 0);
""")
rings = [[(20, 20), (430, 20), (430, 580), (20, 580), (20, 20)],
         [(100, 100), (100, 300), (300, 300), (300, 100), (100, 100)]]
wkb = struct.pack("<BII", 1, 3, len(rings))
for ring in rings:
    wkb += struct.pack("<I", len(ring)) + b"".join(struct.pack("<dd", x, y) for x, y in ring)
header = b"GP" + bytes([0, 1]) + struct.pack("<i", -1)  # version 0, little endian, no envelope
db.execute("INSERT INTO slides (geom) VALUES (?)", (header + wkb,))
db.commit()
PY
if measure_json holed_txt_out "$a" "$b" --weights=mask:"$tmp/holed.txt" --mask_mode=exclude --domain=hull &&
   measure_json holed_gpkg_out "$a" "$b" --weights=mask:"$tmp/holed.gpkg" --mask_mode=exclude --domain=hull; then
  check "a GeoPackage exclude mask with a hole = the same text rings excluded" "
t, g = r('holed_txt_out'), r('holed_gpkg_out')
assert g['mask_rings'] == 2 and g['mask_mode'] == 'exclude', g
for key in ('rho_d', 'weight_integral', 'signed_volume', 'volume_above'):
    assert close(g[key], t[key], 1e-12), (key, g[key], t[key])
"
fi
cat >"$tmp/lines.geojson" <<'JSON'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1]]}},
 {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[2, 0], [1, 1]]}},
 {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[3, 0], [1, 1]]}}]}
JSON
cat >"$tmp/twisted.geojson" <<'JSON'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 7, "properties": {}, "geometry": {"type": "Polygon", "coordinates": [
   [[20, 20], [430, 20], [430, 580], [20, 580], [20, 20]],
   [[100, 100], [300, 300], [300, 100], [100, 250], [100, 100]]]}}]}
JSON
printf '0 0\n400 0\n400 400\n0 400\n>\n300 300\n500 300\n500 500\n300 500\n' >"$tmp/crossing.txt"
echo 'not a geopackage' >"$tmp/landslide.gpkg"
expect_input_error "$tmp/lines.geojson: layer 'lines' has no polygon features (found 3 LineString)" \
  measure "$a" "$b" --weights=mask:"$tmp/lines.geojson"
expect_input_error "$tmp/holed.geojson: no layer 'slides' (layers: 'holed')" \
  measure "$a" "$b" --weights=mask:"$tmp/holed.geojson" --mask_layer=slides
expect_input_error "$tmp/twisted.geojson: feature 7 ring 2 edges 1 and 3 cross: the polygon must be simple" \
  measure "$a" "$b" --weights=mask:"$tmp/twisted.geojson"
expect_input_error "$tmp/crossing.txt: ring 1 and ring 2 cross or touch" \
  measure "$a" "$b" --weights=mask:"$tmp/crossing.txt"
expect_input_error "$tmp/landslide.gpkg: cannot read as a vector file" \
  measure "$a" "$b" --weights=mask:"$tmp/landslide.gpkg"
expect_input_error "flag '--mask_mode': needs a mask (weights mask:FILE)" \
  measure "$a" "$b" --mask_mode=exclude
expect_input_error "'--mask_mode'" measure "$a" "$b" --weights=mask:"$tmp/holed.txt" --mask_mode=maybe

echo "$checks checks, $failures failed"
[[ $failures -eq 0 ]]

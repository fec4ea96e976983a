#!/usr/bin/env bash
# A build without GDAL or Cairo (cmake -DSURFREG_GDAL=OFF / -DSURFREG_PLOTS=OFF,
# or their packages missing): --version says which parts are missing, and
# whatever needs them is refused with exit 2 and one line saying so, before
# any long work and with no output file; clouds are measured and aligned as
# in a full build.
# Usage: without_optional_parts_test.sh SURFREG_BINARY   (run from the project root)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
data=$PWD/configs/data
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/out"
failures=0
checks=0

# refused TEXT ARGS...: exit 2, one line "surfreg: error: ...TEXT...", no output file.
refused() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $(wc -l <"$tmp/stderr") -ne 1 ]] || ! grep -q "^surfreg: error: .*$text" "$tmp/stderr"; then
    fail "surfreg $*: expected one error line containing '$text'"
  elif [[ -n $(ls -A "$tmp/out") ]]; then
    fail "surfreg $*: wrote $(ls -A "$tmp/out")"
  fi
}

run --version
version=$(cat "$tmp/stdout" "$tmp/stderr")
gdal=yes plots=yes
grep -q "rasters and CRSs: no, built without GDAL" <<<"$version" && gdal=no
grep -q "PNG figures: no, built without Cairo" <<<"$version" && plots=no
checks=$((checks + 1))
if [[ $gdal == yes && $plots == yes ]]; then
  fail "--version names no missing part: '$version' (this test is for builds without GDAL or Cairo)"
fi

if [[ $gdal == no ]]; then
  refused "volcano_dem.tif: needs GDAL, but this surfreg was built without GDAL" \
    measure "$data/volcano_dem.tif" "$data/volcano_dem_moved.tif"
  refused "needs GDAL, but this surfreg was built without GDAL" \
    align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --reference_crs=EPSG:32760 \
    --moving_crs=EPSG:32760 --output="$tmp/out/t.json"
fi
if [[ $plots == no ]]; then
  refused "flag '--dod_png': PNG figures need Cairo, and this surfreg was built without it" \
    align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --dod_png="$tmp/out/d.png" \
    --output="$tmp/out/t.json"
  refused "flag '--map': PNG figures need Cairo" asymmetry "$data/face_a.xyz" --map="$tmp/out/m.png"
fi

# Clouds: the full build's numbers (the volcano pair's known motion is recovered).
run align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --output="$tmp/out/t.json"
checks=$((checks + 1))
if [[ $rc -ne 0 ]] || ! grep -q '"verdict": "converged_improved"' "$tmp/out/t.json" 2>/dev/null; then
  fail "align of two clouds: expected exit 0 and verdict converged_improved"
fi

echo "$checks checks, $failures failed"
[[ $failures -eq 0 ]]

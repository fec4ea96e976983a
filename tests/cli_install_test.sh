#!/usr/bin/env bash
# The installed package (issue 21): installs the build into a temporary
# prefix, checks the installed headers (exactly the public ones, each
# compiling on its own against the install), builds examples/ against it with
# find_package(surfreg CONFIG), and runs the examples: align_two_surfaces must
# recover the known motion of configs/data/volcano_moved.xyz, and
# measure_two_surfaces must print the installed `surfreg measure`'s measures.
# Usage: cli_install_test.sh CMAKE BUILD_DIR CXX_COMPILER BUILD_TYPE CXX_FLAGS LINKER_FLAGS
# (the build's type and its flags for that type: the projects built against
# the install use them too, so that e.g. the sanitizer build's instrumented
# libraries link, and the examples run instrumented).
# Paths are relative to the project root (this script's parent folder).
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 6 ]]; then
  echo "usage: $0 CMAKE BUILD_DIR CXX_COMPILER BUILD_TYPE CXX_FLAGS LINKER_FLAGS" >&2
  exit 2
fi
cmake=$1
build=$(realpath -- "$2") || exit 2
cxx=$3
config=${4:-Release}
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
root=$PWD
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
# -D settings shared by both projects built against the install.
client=(-DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE="$config"
        -DCMAKE_CXX_FLAGS_"${config^^}"="$5" -DCMAKE_EXE_LINKER_FLAGS_"${config^^}"="$6")
failures=0
checks=0
jobs=$(nproc 2>/dev/null || echo 2)

# step NAME COMMAND...: runs a set-up step (output to $tmp/stdout, stderr);
# a failed step ends the test, since every later one needs it.
step() {
  local name=$1
  shift
  checks=$((checks + 1))
  local start=$SECONDS
  "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  rc=$?
  if [[ $rc -ne 0 ]]; then
    fail "$name"
    echo "$checks checks, $failures failed"
    exit 1
  fi
  echo "  $name: $((SECONDS - start)) s"
}

step "cmake --install" "$cmake" --install "$build" --prefix "$prefix"

# --- the installed headers: the public ones, none of the internal ones ----------
inc=$prefix/include/surfreg
for header in measure/surface.h measure/measures.h registration/align.h \
              registration/rigid_motion.h faces/symmetry.h io/surface_reader.h io/surface_writer.h; do
  checks=$((checks + 1))
  [[ -f "$inc/$header" ]] || fail "public header $header is not installed"
done
checks=$((checks + 1))
internal=$(cd "$inc" && find . -name '*_internal.h' -o -name 'overlay_clip.h' -o -name 'overlay.h' \
  -o -name 'volume_kernel_*.h' -o -name 'volume_accumulator.h' -o -name 'solvers.h' \
  -o -name 'pair_state.h' -o -name 'config_value.h' -o -name 'predicates.h')
[[ -z "$internal" ]] || fail "internal headers are installed: $internal"
checks=$((checks + 1))
[[ -x "$prefix/bin/surfreg" ]] || fail "the surfreg program is not installed in bin/"
# The project's own compile flags stay its own: none reaches a client.
checks=$((checks + 1))
! grep -rq -- "-ffp-contract" "$prefix"/lib*/cmake/surfreg/ 2>/dev/null ||
  fail "the installed package forces -ffp-contract on its clients"

# Every installed header compiles on its own, included twice (pragma once),
# with only the package's include directories: so the installed set is
# closed under #include and nothing reaches into the source tree.
mkdir -p "$tmp/headers"
{
  echo 'cmake_minimum_required(VERSION 3.16)'
  echo 'project(surfreg_header_check LANGUAGES CXX)'
  echo 'find_package(surfreg CONFIG REQUIRED)'
  echo 'add_library(header_check OBJECT'
} >"$tmp/headers/CMakeLists.txt"
n_headers=0
while read -r header; do
  n_headers=$((n_headers + 1))
  printf '#include <surfreg/%s>\n#include <surfreg/%s>\n' "$header" "$header" \
    >"$tmp/headers/h$n_headers.cc"
  echo "  h$n_headers.cc" >>"$tmp/headers/CMakeLists.txt"
done < <(cd "$inc" && find . -name '*.h' | sed 's|^\./||' | sort)
{
  echo ')'
  echo 'target_link_libraries(header_check PRIVATE surfreg::registration surfreg::faces surfreg::io surfreg::terrain)'
  echo 'target_compile_options(header_check PRIVATE -fsyntax-only)'
} >>"$tmp/headers/CMakeLists.txt"
echo "  $n_headers installed headers"
step "configure the header check" "$cmake" -S "$tmp/headers" -B "$tmp/headers/build" \
  "${client[@]}"
step "every installed header compiles on its own" "$cmake" --build "$tmp/headers/build" -j "$jobs"

# --- examples/ against the install ---------------------------------------------
step "configure examples/" "$cmake" -S "$root/examples" -B "$tmp/examples" \
  "${client[@]}"
step "build examples/" "$cmake" --build "$tmp/examples" -j "$jobs"

# Without GDAL (find_package(GDAL) disabled) a client still configures,
# links and runs (an in-memory pair 0.3 apart in z, aligned back), and
# surfreg::io is defined too: its GDAL calls are in the installed module,
# loaded at run time, so a client links no GDAL.
mkdir -p "$tmp/core"
cat >"$tmp/core/CMakeLists.txt" <<'END'
cmake_minimum_required(VERSION 3.16)
project(surfreg_core_check LANGUAGES CXX)
find_package(surfreg CONFIG REQUIRED COMPONENTS ${COMPONENTS})
if(NOT TARGET surfreg::io)
  message(FATAL_ERROR "surfreg::io is not defined without GDAL")
endif()
add_executable(core_check core_check.cc)
target_link_libraries(core_check PRIVATE surfreg::registration)
END
cat >"$tmp/core/core_check.cc" <<'END'
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include <surfreg/registration/align.h>

int main() {
  std::vector<std::array<double, 3>> reference, moving;
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) {
      const double z = 3 * std::sin(i / 5.0) * std::cos(j / 7.0) + 0.01 * i * j;
      reference.push_back({double(i), double(j), z});
      moving.push_back({double(i), double(j), z + 0.3});
    }
  }
  const surfreg::AlignResult result =
      surfreg::Align(surfreg::MakeSurface(reference), surfreg::MakeSurface(moving));
  std::printf("%.9f\n", result.matrix(2, 3));
}
END
step "configure a core-only client without GDAL" "$cmake" -S "$tmp/core" -B "$tmp/core/build" \
  "${client[@]}" -DCMAKE_DISABLE_FIND_PACKAGE_GDAL=ON -DCOMPONENTS="measure;registration"
step "build it" "$cmake" --build "$tmp/core/build"
bin=$tmp/core/build/core_check
run
checks=$((checks + 1))
if [[ $rc -ne 0 ]] || ! awk '{ exit !($1 + 0.3 < 1e-3 && $1 + 0.3 > -1e-3) }' "$tmp/stdout"; then
  fail "core_check: expected the z shift -0.3 back"
else
  echo "  core_check (no GDAL): z shift found $(cat "$tmp/stdout")"
fi

# The GDAL module: installed in lib/surfreg/ (or the libdir's), and the
# installed program reads a GeoTIFF through it; a module that cannot be
# loaded gives one line naming the file and the module, exit 2.
checks=$((checks + 1))
module=$(find "$prefix" -name libsurfreg_gdal.so -path '*/surfreg/*' | head -1)
if [[ $("$prefix/bin/surfreg" --version 2>&1) == *"built without GDAL"* ]]; then
  [[ -z "$module" ]] || fail "a build without GDAL installed $module"
elif [[ -z "$module" ]]; then
  fail "libsurfreg_gdal.so is not installed under lib*/surfreg/"
else
  bin=$prefix/bin/surfreg
  SURFREG_GDAL_MODULE=$module run measure configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif
  [[ $rc -eq 0 ]] && grep -q "rho_d" "$tmp/stdout" ||
    fail "installed surfreg measure of two GeoTIFFs through $module: expected exit 0 and rho_d"
  SURFREG_GDAL_MODULE=$tmp/nothing.so run measure configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif
  [[ $rc -eq 2 ]] && grep -q "volcano_dem.tif: needs GDAL, but cannot load libsurfreg_gdal.so" "$tmp/stderr" ||
    fail "a module that cannot be loaded: expected exit 2 and 'needs GDAL, but cannot load'"
  # examples/terrain_change: the terrain library gives what `surfreg measure
  # --json` prints, to the bit (dz statistics at A's nodes, cut/fill).
  SURFREG_GDAL_MODULE=$module run measure configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif \
    --lod=1.5 --json
  cp "$tmp/stdout" "$tmp/measure.json"
  bin=$tmp/examples/terrain_change
  SURFREG_GDAL_MODULE=$module run configs/data/volcano_dem.tif configs/data/volcano_dem_moved.tif 1.5
  checks=$((checks + 1))
  if [[ $rc -ne 0 ]]; then
    fail "terrain_change of two GeoTIFFs: expected exit 0"
  elif ! result=$(python3 - "$tmp/measure.json" "$tmp/stdout" <<'END'
import json, sys
m = json.load(open(sys.argv[1]))
lines = {l.split()[0]: l.split()[1:] for l in open(sys.argv[2]) if l.strip()}
example = {k: float(v) for k, v in zip(lines["dz"][0::2], lines["dz"][1::2])}
example.update({"change_" + k: float(v) for k, v in zip(lines["change"][0::2], lines["change"][1::2])})
pairs = [("count", m["dz"]["count"]), ("mean", m["dz"]["mean"]), ("median", m["dz"]["median"]),
         ("nmad", m["dz"]["nmad"]), ("stddev", m["dz"]["stddev"]), ("rmse", m["dz"]["rmse"]),
         ("change_lod", m["change"]["level_of_detection"]), ("change_fill", m["change"]["fill"]),
         ("change_cut", m["change"]["cut"]), ("change_net", m["change"]["net"])]
bad = [(k, example[k], v) for k, v in pairs if example[k] != v]
assert not bad, bad
assert m["change"]["fill"] > 0 and m["change"]["cut"] > 0 and m["dz"]["count"] > 1000, m["change"]
print("dz median %.4g, NMAD %.4g over %d nodes; fill %.6g, cut %.6g" % (
    example["median"], example["nmad"], example["count"], example["change_fill"], example["change_cut"]))
END
  ); then
    fail "terrain_change differs from surfreg measure --json: $result"
  else
    echo "  terrain_change = surfreg measure --json: $result"
  fi
fi

# align_two_surfaces: the printed matrix against the known motion (the
# moved file's header line "# reference_from_moving: [[...], ...]"), as the
# rotation between them and the largest distance between where the two put
# the moving surface's bounding-box corners (at its mean height) and centroid.
ref=configs/data/volcano_a.xyz
mov=configs/data/volcano_moved.xyz
bin=$tmp/examples/align_two_surfaces
run "$ref" "$mov"
if [[ $rc -ne 0 ]]; then
  fail "align_two_surfaces $ref $mov: expected exit 0"
else
  checks=$((checks + 1))
  truth=$(sed -n 's/^# reference_from_moving: //p' "$mov" | tr -d '[],')
  if ! result=$(awk -v truth="$truth" -v found="$(cat "$tmp/stdout")" '
    function fail(message) { print message; bad = 1; exit 1 }
    BEGIN {
      if (split(truth, t, " ") != 16) fail("no known motion in the moved file")
      if (split(found, f, /[ \n]+/) != 16) fail("expected 4 lines of 4 numbers")
      for (i = 1; i <= 16; ++i) if (f[i] !~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/) fail("not a number: " f[i])
      if (f[13] != 0 || f[14] != 0 || f[15] != 0 || f[16] != 1) fail("last row is not 0 0 0 1")
    }
    !/^#/ && NF >= 3 {
      n += 1; x[n] = $1; y[n] = $2; z[n] = $3
      sx += $1; sy += $2; sz += $3
      if (n == 1 || $1 < x0) x0 = $1; if (n == 1 || $1 > x1) x1 = $1
      if (n == 1 || $2 < y0) y0 = $2; if (n == 1 || $2 > y1) y1 = $2
    }
    END {
      if (bad) exit 1
      # trace(R_found^T R_true) = 1 + 2 cos(angle)
      trace = 0
      for (r = 0; r < 3; ++r) for (c = 1; c <= 3; ++c) trace += f[4 * r + c] * t[4 * r + c]
      cosine = (trace - 1) / 2; if (cosine > 1) cosine = 1
      angle = atan2(sqrt(1 - cosine * cosine), cosine) * 45 / atan2(1, 1)
      spacing = sqrt((x1 - x0) * (y1 - y0) / n)
      px[1] = x0; py[1] = y0; px[2] = x0; py[2] = y1; px[3] = x1; py[3] = y0; px[4] = x1; py[4] = y1
      px[5] = sx / n; py[5] = sy / n
      worst = 0
      for (k = 1; k <= 5; ++k) {
        d2 = 0
        for (r = 0; r < 3; ++r) {
          i = 4 * r
          d = (f[i + 1] - t[i + 1]) * px[k] + (f[i + 2] - t[i + 2]) * py[k] + \
              (f[i + 3] - t[i + 3]) * sz / n + f[i + 4] - t[i + 4]
          d2 += d * d
        }
        if (sqrt(d2) > worst) worst = sqrt(d2)
      }
      printf "rotation off by %.5f deg, points off by %.3g (spacing %.3g)\n", angle, worst, spacing
      # As tests/cli_align_test.sh for this pair with its config.
      if (angle >= 0.05 || worst >= 0.1 * spacing) exit 1
    }' "$mov"); then
    fail "align_two_surfaces did not recover the known motion: $result"
  else
    echo "  align_two_surfaces: $result"
  fi
fi

# measure_two_surfaces: the measures of the installed `surfreg measure --json`.
a=configs/data/volcano_a.xyz
b=configs/data/volcano_b.xyz
bin=$tmp/examples/measure_two_surfaces
run "$a" "$b"
if [[ $rc -ne 0 ]]; then
  fail "measure_two_surfaces $a $b: expected exit 0"
else
  cp "$tmp/stdout" "$tmp/example.txt"
  bin=$prefix/bin/surfreg
  run measure "$a" "$b" --json
  if [[ $rc -ne 0 ]]; then
    fail "installed surfreg measure $a $b --json: expected exit 0"
  else
    for key in rho_d rho_d_axial rho_s overlap_area mean_abs_dz; do
      checks=$((checks + 1))
      mine=$(awk -v k="$key" '$1 == k { print $2 }' "$tmp/example.txt")
      cli=$(grep -o "\"$key\": *[-0-9.e+]*" "$tmp/stdout" | head -1 | sed 's/.*: *//')
      awk -v m="$mine" -v c="$cli" 'BEGIN { d = m - c; if (d < 0) d = -d
        exit !(m != "" && c != "" && c + 0 > 0 && d <= 1e-6 * c) }' ||
        fail "measure_two_surfaces: $key is '$mine', surfreg measure says '$cli'"
    done
    echo "  measure_two_surfaces: $(tr '\n' ' ' <"$tmp/example.txt")"
  fi
fi
# Bad input: one error line, exit 2.
bin=$tmp/examples/measure_two_surfaces
run "$a" "$tmp/missing.xyz"
[[ $rc -eq 2 && $(wc -l <"$tmp/stderr") -eq 1 ]] ||
  fail "measure_two_surfaces with a missing file: expected exit 2 and one error line"

echo "$checks checks, $failures failed"
[[ $failures -eq 0 ]]

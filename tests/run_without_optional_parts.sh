#!/usr/bin/env bash
# The suite of a build without the optional parts (issue 21): GDAL and Cairo
# OFF, in its own build directory (part of .ci/run). The libraries, the CLI
# and every test that needs neither must build and pass; the tests of
# rasters, CRSs and figures are left out (and so are the long whole-pipeline
# runs of tests/heavy_tests.txt, which the Release build runs), and
# tests/without_optional_parts_test.sh checks that those are refused with
# one line.
#
#   bash tests/run_without_optional_parts.sh        configure, build, run ctest
#   SURFREG_LITE_BUILD_DIR=dir ...                  build somewhere else (default build-lite)
#
# -O1 without LTO: this build is about what compiles and links, and -O1
# keeps both the build and the run short.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${SURFREG_LITE_BUILD_DIR:-build-lite}"
jobs="$(nproc 2>/dev/null || echo 2)"
echo "== configuring without GDAL and Cairo in $build_dir"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Lite -DCMAKE_CXX_FLAGS_LITE="-O1" \
  -DSURFREG_GDAL=OFF -DSURFREG_PLOTS=OFF \
  -DSURFREG_BUILD_BENCHMARKS=OFF -DSURFREG_FUZZ=OFF -DSURFREG_PYTHON=OFF >/dev/null
echo "== building"
cmake --build "$build_dir" -j "$jobs"
source tests/heavy_tests_regex.sh
echo "== testing (without the long runs in tests/heavy_tests.txt)"
ctest --test-dir "$build_dir" -j "$jobs" --output-on-failure --timeout 900 \
  -E "$(heavy_tests_regex tests/heavy_tests.txt)"

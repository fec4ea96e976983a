#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (GCC),
# in its own build directory (part of .ci/run): every test but the long
# whole-pipeline runs named in tests/heavy_tests.txt, which the Release
# build runs.
#
#   bash tests/run_sanitizers.sh            configure, build, run ctest
#   SURFREG_SANITIZER_BUILD_DIR=dir ...     build somewhere else (default build-sanitizers)
#
# -O1 keeps the run fast enough for CI while the sanitizers still see every
# access, -g1 (line tables) is all a report's stack needs; NDEBUG is not defined, so assert()s are on too. Any report (leak,
# out-of-bounds access, undefined behaviour) aborts the test that made it,
# and the script fails if any test fails. Leak reports that come from the
# libraries we use, not from surfreg, are suppressed narrowly in
# tests/lsan.supp (each entry says why).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
build_dir="${SURFREG_SANITIZER_BUILD_DIR:-build-sanitizers}"
jobs="$(nproc 2>/dev/null || echo 2)"

sanitize="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
# Eigen stops trusting malloc's 16-byte alignment under ASan and then frees
# with its own aligned free (reading a header before the block); Ceres, built
# without ASan, allocates with plain malloc matrices our code frees (e.g.
# GradientChecker's results). Keep both sides on plain malloc/free.
eigen="-DEIGEN_MALLOC_ALREADY_ALIGNED=1"
echo "== configuring the sanitizer build (GCC, ASan + UBSan, -O1 -g1) in $build_dir"
# Tests are discovered when ctest runs (PRE_TEST), not at link time, so that
# the build itself never runs an instrumented program.
cmake -S . -B "$build_dir" \
  -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_CXX_COMPILER=g++ \
  -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1 $sanitize $eigen" \
  -DCMAKE_EXE_LINKER_FLAGS_SANITIZE="$sanitize" \
  -DCMAKE_SHARED_LINKER_FLAGS_SANITIZE="$sanitize" \
  -DCMAKE_GTEST_DISCOVER_TESTS_DISCOVERY_MODE=PRE_TEST \
  -DSURFREG_BUILD_BENCHMARKS=OFF -DSURFREG_FUZZ=OFF \
  -DSURFREG_PYTHON=OFF >/dev/null  # an ASan module cannot load into an uninstrumented python3
echo "== building"
cmake --build "$build_dir" -j "$jobs"

# intercept_tls_get_addr=0: GCC 12's LeakSanitizer records the dynamic TLS
# of libraries loaded with dlopen (surfreg loads GDAL's that way) and, with
# glibc 2.36, can record a bogus range for one (seen: "DTLS 17 at
# 0x5b3-0x10000016b5" under LSAN_OPTIONS=verbosity=1:log_threads=1); its
# tracer then faults reading it at exit ("Tracer caught signal 11:
# addr=0x5b8"). Whether the range is bogus depends on the memory layout, so
# a command crashed with some file paths and not others. Without the
# interception LSan does not scan dynamic TLS as roots; a block held only
# there would show as a leak, never hide one.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1:detect_invalid_pointer_pairs=0:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0"
source tests/heavy_tests_regex.sh
heavy=$(heavy_tests_regex tests/heavy_tests.txt)
# A name in the list that no longer exists would leave nothing out silently.
listed=$(grep -cv '^[[:space:]]*\(#\|$\)' tests/heavy_tests.txt)
found=$(ctest --test-dir "$build_dir" -N -R "$heavy" | grep -c '^ *Test *#' || true)
if [ "$found" -ne "$listed" ]; then
  echo "error: tests/heavy_tests.txt names $listed tests, ctest knows $found of them" >&2
  exit 1
fi
echo "== running the test suite under ASan + UBSan (without the $listed in tests/heavy_tests.txt)"
ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" --timeout 600 -E "$heavy"

#!/usr/bin/env bash
# The tests of the parallel stages under ThreadSanitizer (GCC), in their own
# build directory (part of .ci/run): the overlay in chunks, the volume
# cost's cache and Hessian, the location of both clouds side by side, the
# sandwich's tile sums, the grid paths' row chunks, the spanning tree's
# range forests, the Hilbert order's radix passes, the dz statistics'
# selection, a raster read by bands of rows, the task primitives and the
# thread-count determinism tests (1 to 8 threads). The chunks run on
# plain std::threads here (SURFREG_TASKS_STD_THREADS): ThreadSanitizer cannot
# see the synchronization inside the uninstrumented libtbb, and would report
# its hand-overs as races. Only these test programs are built, so the step
# stays short.
#
#   bash tests/run_thread_sanitizer.sh          configure, build, run them
#   SURFREG_TSAN_BUILD_DIR=dir ...              build somewhere else (default build-tsan)
#
# Any report (a data race, a lock-order inversion) fails the test that made
# it (halt_on_error), and the script fails if any test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${SURFREG_TSAN_BUILD_DIR:-build-tsan}"
jobs="$(nproc 2>/dev/null || echo 2)"
targets=(thread_determinism_test overlay_test overlay_topology_test volume_hessian_test pair_state_test
         measures_test grid_pair_test raster_pair_test domain_test stable_terrain_test tasks_test
         delaunay_slabs_test spanning_tree_test locator_test surface_reader_test spatial_sort_test change_test
         raster_io_test raster_write_test raster_samples_test grid_mesh_test series_test jaw_test raster_resample_test)
# Of long programs, only the tests of their parallel stages.
declare -A filter=([stable_terrain_test]="SampleAdjacency.*" [delaunay_slabs_test]="*:-*LargeInput*" [spanning_tree_test]="*SameTree*:*CycleProperty*" [locator_test]="*InChunks*" [surface_reader_test]="XyzChunks.*" [spatial_sort_test]="*SameOrder*" [change_test]="DzStatistics.*" [raster_io_test]="*ByBandsOfRows*" [raster_write_test]="*AnyThreadCount*" [grid_mesh_test]="*ByChunks*" [series_test]="*AtOnce*:*FirstFailing*" [jaw_test]="*OneAndTwoThreads*" [raster_resample_test]="*Threads*")
sanitize="-fsanitize=thread -fno-omit-frame-pointer"
echo "== configuring the ThreadSanitizer build (GCC, -O1 -g1) in $build_dir"
cmake -S . -B "$build_dir" \
  -DCMAKE_BUILD_TYPE=Tsan \
  -DCMAKE_CXX_COMPILER=g++ \
  -DCMAKE_CXX_FLAGS_TSAN="-O1 -g1 $sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS_TSAN="$sanitize" \
  -DCMAKE_SHARED_LINKER_FLAGS_TSAN="$sanitize" \
  -DCMAKE_GTEST_DISCOVER_TESTS_DISCOVERY_MODE=PRE_TEST -DSURFREG_TASKS_STD_THREADS=ON \
  -DSURFREG_BUILD_BENCHMARKS=OFF -DSURFREG_FUZZ=OFF -DSURFREG_PYTHON=OFF >/dev/null
echo "== building ${targets[*]}"
cmake --build "$build_dir" -j "$jobs" --target "${targets[@]}"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/tsan_suppressions.txt"
status=0
for t in "${targets[@]}"; do
  echo "== $t under ThreadSanitizer"
  if ! "$build_dir/tests/$t" --gtest_brief=1 --gtest_filter="${filter[$t]:-*}"; then
    echo "FAIL: $t under ThreadSanitizer" >&2
    status=1
  fi
done
exit $status

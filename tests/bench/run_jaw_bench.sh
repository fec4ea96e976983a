#!/usr/bin/env bash
# Builds and runs the jaw benchmark (tests/bench/jaw_bench.cc, Google
# Benchmark): a 30-frame chewing sequence of 2 × 20k-point halves tracked by
# surfreg's jaw tracker, against full Measure() calls of one 40k-vs-40k frame
# pair, in one run; counter ratio_to_target = the run / 60 measures (target
# < 1), with the accuracy against the generated truth.
#
#   tests/bench/run_jaw_bench.sh [build_dir] [jaw_bench flags, e.g. --variants]
#
# build_dir defaults to build-bench at the top of the source tree (configured
# Release if new). Exit status: that of jaw_bench (2 = target missed).
set -euo pipefail
script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source_dir=$(cd "$script_dir/../.." && pwd)
build_dir=${1:-$source_dir/build-bench}
[[ $# -gt 0 ]] && shift
if [[ ! -f $build_dir/CMakeCache.txt ]]; then
  cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build_dir" -j2 --target jaw_bench
"$build_dir/tests/bench/jaw_bench" "$@"

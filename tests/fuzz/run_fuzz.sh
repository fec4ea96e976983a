#!/usr/bin/env bash
# Builds the libFuzzer programs (clang, ASan + UBSan, SURFREG_FUZZ=ON) in their
# own build directory and runs each for SECONDS (default 60) on a copy of its
# seed corpus tests/fuzz/corpus/<target>/ (issue 7; part of .ci/run).
#
#   bash tests/fuzz/run_fuzz.sh [SECONDS]
#   SURFREG_FUZZ_BUILD_DIR=dir   build directory (default build-fuzz)
#   SURFREG_FUZZ_JOBS=n          targets run at the same time (default: the cores)
#   SURFREG_FUZZ_TARGETS="ply measure"   only these targets
#
# A target fails on a crash, an exception other than InputError, a broken
# invariant, a leak, an input slower than 10 s (-timeout) or more than 2 GiB
# of memory (-rss_limit_mb). The failing input is saved as
# <build>/fuzz-out/<target>/crash-* (or leak-*, timeout-*, oom-*) and the
# script fails. After fixing the bug, copy that input into
# tests/fuzz/corpus/<target>/ under a name that says what it found: from then
# on fuzz_corpus_test runs it in every build. The inputs a run discovers are
# left in <build>/fuzz-out/<target>/corpus, never in the source tree.
set -euo pipefail
cd "$(dirname "$0")/../.."
root="$(pwd)"
seconds="${1:-60}"
build_dir="${SURFREG_FUZZ_BUILD_DIR:-build-fuzz}"
jobs="${SURFREG_FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}"
targets="${SURFREG_FUZZ_TARGETS:-xyz ply off obj las polygon align_config measure mesh jaw_config sweep_config}"

case "$build_dir" in /*) ;; *) build_dir="$root/$build_dir" ;; esac
if ! command -v clang++ >/dev/null; then
  echo "error: clang++ not found (bash tools/setup.sh test installs it)" >&2
  exit 1
fi

instrument="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
echo "== configuring the fuzz build (clang, libFuzzer + ASan + UBSan) in $build_dir"
cmake -S . -B "$build_dir" \
  -DCMAKE_BUILD_TYPE=Fuzz \
  -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$instrument" -DCMAKE_CXX_FLAGS_FUZZ="-O1 -g1" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DSURFREG_FUZZ=ON -DSURFREG_BUILD_BENCHMARKS=OFF >/dev/null
echo "== building the fuzz targets"
cmake --build "$build_dir" -j "$(nproc 2>/dev/null || echo 2)" --target surfreg_fuzzers

# One target: fuzz a fresh copy of its corpus; the log goes to fuzz-out/<t>.log.
run_target() {
  local target="$1" out="$build_dir/fuzz-out/$1"
  rm -rf "$out"
  mkdir -p "$out/corpus"
  cp "$root/tests/fuzz/corpus/$target/"* "$out/corpus/"
  if "$build_dir/tests/fuzz/fuzz_$target" "$out/corpus" \
      -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$out/" >"$out.log" 2>&1; then
    echo "ok    $target: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$out.log" |
                          grep -o '[0-9]*$') runs in ${seconds} s"
  else
    echo "FAIL  $target: see $out.log and $out/"
    grep -E 'ERROR|SUMMARY|fuzz invariant|terminate called|what\(\)' "$out.log" | head -5
    return 1
  fi
}
export -f run_target
export build_dir root seconds

echo "== fuzzing each target for $seconds s ($jobs at a time)"
mkdir -p "$build_dir/fuzz-out"
# xargs exits non-zero if any target failed; every target still runs.
printf '%s\n' $targets | xargs -P "$jobs" -I{} bash -c 'run_target {}'
echo "== all fuzz targets passed"

#!/usr/bin/env bash
# One-step set-up for surfreg on Debian 12:
#   bash tools/setup.sh run    install what is missing, build the program and the Python module (Release),
#                              run the quick start
#   bash tools/setup.sh test   install what is missing, build everything (warnings are errors), run ctest
# Installs only Debian packages that are not installed yet (needs root or sudo
# for that step); builds into ./build (override with SURFREG_BUILD_DIR).
set -euo pipefail

mode="${1:-}"
case "$mode" in
  run|test) ;;
  *) echo "usage: bash tools/setup.sh run|test" >&2; exit 2 ;;
esac

cd "$(dirname "$0")/.."
build_dir="${SURFREG_BUILD_DIR:-build}"
jobs="$(nproc 2>/dev/null || echo 2)"

# Build tools and libraries; libcgal-dev is only the benchmark's reference
# (the build works without it), python3 checks the CLI's JSON in the tests,
# clang and libclang-rt-14-dev (the libFuzzer and sanitizer runtimes, only
# recommended by clang, so named here) build tests/fuzz/run_fuzz.sh's fuzzers.
# pybind11-dev, python3-dev and python3-numpy build and run the Python module
# (tools/python), python3-pytest tests it.
packages=(cmake make g++ pkg-config libceres-dev libeigen3-dev libgoogle-glog-dev libgflags-dev
          libgeographiclib-dev libyaml-cpp-dev libgdal-dev libcairo2-dev libgtest-dev libbenchmark-dev
          pybind11-dev python3-dev python3-numpy libtbb-dev)
if [ "$mode" = test ]; then packages+=(libcgal-dev python3 parallel clang libclang-rt-14-dev python3-pytest); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "== installing: ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null; then sudo=sudo; else
      echo "error: need root (or sudo) to install: ${missing[*]}" >&2; exit 1
    fi
  fi
  # Quiet on success; apt's errors (a missing package, no network, a held
  # lock) are shown in full.
  apt_log=$(mktemp)
  if ! { $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq \
           --no-install-recommends "${missing[@]}"; } >"$apt_log" 2>&1; then
    cat "$apt_log" >&2
    rm -f "$apt_log"
    echo "error: apt-get could not install: ${missing[*]} (its output is above)" >&2
    exit 1
  fi
  rm -f "$apt_log"
fi

# run: only the program and the Python module the quick start uses (the
# tests and benchmarks are built by `test`); test: everything, with the
# compiler's warnings as errors.
echo "== configuring and building (Release) in $build_dir"
if [ "$mode" = run ]; then
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build_dir" -j "$jobs" --target surfreg
  targets=$(cmake --build "$build_dir" --target help)  # not piped: grep -q would cut it short under pipefail
  if grep -qw surfreg_python <<<"$targets"; then
    cmake --build "$build_dir" -j "$jobs" --target surfreg_python
  fi
else
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSURFREG_WERROR=ON >/dev/null
  cmake --build "$build_dir" -j "$jobs"
fi

if [ "$mode" = run ]; then
  echo "== default job (README, quick start): surfreg align --config configs/terrain_volcano.yaml"
  mkdir -p out
  "$build_dir/tools/surfreg" align --config configs/terrain_volcano.yaml
else
  echo "== running the test suite"
  ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
fi

#!/usr/bin/env bash
# One-step set-up for surfreg on Debian 12:
#   bash tools/setup.sh run    install what is missing, build (Release), run the default job
#   bash tools/setup.sh test   install what is missing, build, run the whole test suite (ctest)
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
          pybind11-dev python3-dev python3-numpy)
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
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
fi

echo "== configuring and building (Release) in $build_dir"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "$jobs"

if [ "$mode" = run ]; then
  echo "== default job (README, quick start): surfreg align --config configs/terrain_volcano.yaml"
  mkdir -p out
  "$build_dir/tools/surfreg" align --config configs/terrain_volcano.yaml
else
  echo "== running the test suite"
  ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
fi

#!/usr/bin/env bash
# Registration accuracy of `surfreg align` against Open3D point-to-plane ICP
# and generalized ICP on the same pairs from the same start; prints Markdown.
#
#   tests/bench/run_align_peers.sh [--changed] [--out DIR] [--surfreg BIN] [--seeds N]
#                                  [--keep-pairs] [extra run_peers.py flags...]
#
# --changed: the changed pairs of align_peers/make_changed_pairs.py instead
# (terrain that changed between the surveys, a face whose jaw moved), with
# surfreg's default, --stable=all and the oracle beside the peers, and
# DIR/changed_summary.md (align_peers/changed_summary.py; DIR defaults to
# build/bench-results/changed_peers, N to 4).
#
# Installs the missing Debian packages (python3-numpy, -scipy, -open3d; the
# build dependencies too when it builds), builds surfreg into ./build unless
# --surfreg is given, writes the pairs into a temporary directory (kept under
# DIR/pairs with --keep-pairs), runs all methods, and writes DIR/align_peers.md
# (the tables, also printed) and DIR/align_peers.csv (one row per pair x
# method). DIR defaults to build/bench-results/align_peers.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
here=$root/tests/bench/align_peers
out_dir=""
surfreg=""
seeds=""
keep=0
changed=0
extra=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --changed) changed=1; shift ;;
    --out) out_dir=$2; shift 2 ;;
    --surfreg) surfreg=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --keep-pairs) keep=1; shift ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) extra+=("$1"); shift ;;
  esac
done
if [[ $changed -eq 1 ]]; then
  out_dir=${out_dir:-$root/build/bench-results/changed_peers}
  seeds=${seeds:-4}
  make_pairs=(make_changed_pairs.py)
  extra=(--methods surfreg,surfreg_all,surfreg_oracle,icp_plane,gicp "${extra[@]}")
else
  out_dir=${out_dir:-$root/build/bench-results/align_peers}
  seeds=${seeds:-3}
  make_pairs=(make_pairs.py)
fi

# Debian's python3 (with the Debian numpy/scipy/open3d), not a pyenv/venv one
# that may come first on PATH.
py=/usr/bin/python3
packages=(python3 python3-numpy python3-scipy python3-open3d)
if [[ -z $surfreg ]]; then
  packages+=(cmake make g++ pkg-config libceres-dev libeigen3-dev libgoogle-glog-dev libgflags-dev
             libgeographiclib-dev libyaml-cpp-dev libgtest-dev libbenchmark-dev)
fi
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [[ ${#missing[@]} -gt 0 ]]; then
  echo "== installing: ${missing[*]}" >&2
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then
    if command -v sudo >/dev/null; then sudo=sudo; else
      echo "error: need root (or sudo) to install: ${missing[*]}" >&2; exit 1
    fi
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
fi

# Build (incremental; a failed build is only a warning: surfreg is then n/a
# unless an older binary is there).
if [[ -z $surfreg ]]; then
  surfreg=$root/build/tools/surfreg
  echo "== building surfreg (Release) in $root/build" >&2
  if { [[ -f $root/build/CMakeCache.txt ]] ||
       cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null; } &&
     cmake --build "$root/build" --target surfreg -j "$(nproc 2>/dev/null || echo 2)" >/dev/null; then
    :
  else
    echo "warning: building surfreg failed; using $surfreg if present" >&2
  fi
fi

pairs=$(mktemp -d "${TMPDIR:-/tmp}/align_peers.XXXXXX")
cleanup() { rm -rf "$pairs"; }
trap cleanup EXIT
mkdir -p "$out_dir"
start=$(date +%s)

echo "== making pairs ($seeds seeds per family and variant)" >&2
"$py" "$here/${make_pairs[0]}" --data "$root/configs/data" --out "$pairs" --seeds "$seeds" >"$out_dir/pairs.log"
echo "== running surfreg and the peers (progress below; pairs listed in $out_dir/pairs.log)" >&2
"$py" "$here/run_peers.py" --pairs "$pairs" --out "$out_dir" --surfreg "$surfreg" "${extra[@]}"
if [[ $changed -eq 1 ]]; then
  "$py" "$here/changed_summary.py" "$out_dir/align_peers.csv" --out "$out_dir/changed_summary.md"
fi

if [[ $keep -eq 1 ]]; then
  rm -rf "$out_dir/pairs"
  cp -r "$pairs" "$out_dir/pairs"
fi
echo "== done in $(($(date +%s) - start)) s: $out_dir/align_peers.md, $out_dir/align_peers.csv" >&2

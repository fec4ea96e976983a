#!/usr/bin/env bash
# Outputs that cannot be written (issue 23): past a file-size limit
# (`ulimit -f`, which without our handling kills the process with SIGXFSZ)
# and to a full device (/dev/full as stdout). Each must end with exit 2 and
# one line "surfreg: error: ..." naming the file (or the standard output),
# and leave no file and no temporary behind.
# Usage: cli_full_disk_test.sh SURFREG_BINARY   (run from the project root)
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
failures=0
checks=0

# limited KIB EXPECTED_FILE ARGS...: runs the command under `ulimit -f KIB`
# and checks exit 2, one error line naming EXPECTED_FILE, and an empty out/.
limited() {
  local kib=$1 file=$2
  shift 2
  rm -rf "$tmp/out" && mkdir "$tmp/out"
  checks=$((checks + 1))
  # --quiet: the limit holds for stderr's file too, and a slow build (the
  # sanitizers') prints progress lines that would fill it first.
  (ulimit -f "$kib" && exec "$bin" "$@" --quiet) >"$tmp/stdout" 2>"$tmp/stderr"
  rc=$?
  local errors
  errors=$(grep -c '^surfreg: error:' "$tmp/stderr")
  if [[ $rc -ne 2 ]]; then
    fail "ulimit -f $kib: $*: expected exit 2, got $rc"
  elif [[ $errors -ne 1 ]] || ! grep -q "^surfreg: error: .*$file.*File too large" "$tmp/stderr"; then
    fail "ulimit -f $kib: $*: expected one error line naming $file and 'File too large'"
  elif [[ -n "$(ls -A "$tmp/out")" ]]; then
    fail "ulimit -f $kib: $*: files left behind: $(ls -A "$tmp/out")"
  fi
}

limited 1 out/log.csv align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --log="$tmp/out/log.csv"
limited 1 out/run.json align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --output="$tmp/out/run.json"
limited 4 out/aligned.xyz align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --aligned="$tmp/out/aligned.xyz"
limited 4 out/dod.tif align "$data/volcano_dem.tif" "$data/volcano_dem_moved.tif" --output="$tmp/out/dod.tif"
limited 4 out/dod.png align "$data/volcano_dem.tif" "$data/volcano_dem_moved.tif" --dod_png="$tmp/out/dod.png"
limited 1 "standard output" measure "$data/volcano_a.xyz" "$data/volcano_b.xyz" --json

# A full device as stdout: the results must not be lost silently.
for command in "measure $data/volcano_a.xyz $data/volcano_b.xyz --json" \
               "measure $data/volcano_a.xyz $data/volcano_b.xyz"; do
  checks=$((checks + 1))
  # shellcheck disable=SC2086  # the command's words
  "$bin" $command >/dev/full 2>"$tmp/stderr"
  rc=$?
  if [[ $rc -ne 2 ]] || ! grep -q "^surfreg: error: cannot write the standard output: No space left" "$tmp/stderr"; then
    fail "$command > /dev/full: expected exit 2 and 'cannot write the standard output: No space left'"
  fi
done

echo "$checks checks, $failures failed"
[[ $failures -eq 0 ]]

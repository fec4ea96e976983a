#!/usr/bin/env bash
# End-to-end tests of `surfreg sweep`, `surfreg merge` and `surfreg align
# --manifest`: a small grid run whole, in 3 shards (GNU parallel when
# installed, else a loop) then merged, and killed part-way then resumed; the
# rows must be the same (the timing column aside). The plots must be PNG
# files that decode; the summary must rank every setting. Bad usage must be
# one error line and exit 2.
# Usage: cli_sweep_test.sh SURFREG_BINARY
# Needs python3 (standard library). Paths are relative to the project root.
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0

# expect_error TEXT ARGS...: exit 2 and a "surfreg: error:" line containing TEXT.
expect_error() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2, got $rc"
  elif ! grep -q '^surfreg: error: ' "$tmp/stderr" || ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: expected an error line containing '$text'"
  fi
}

# same_rows A.csv B.csv: equal header and rows, the column 'seconds' aside.
same_rows() {
  checks=$((checks + 1))
  python3 - "$1" "$2" <<'EOF' || fail "rows of $1 and $2 differ"
import csv, sys
def rows(path):
    with open(path, newline='') as f:
        table = list(csv.reader(f))
    drop = table[0].index('seconds')
    return [row[:drop] + row[drop + 1:] for row in table]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
if a != b:
    print(f"  {len(a)} vs {len(b)} lines; first difference:", next(((x, y) for x, y in zip(a, b) if x != y), None))
    sys.exit(1)
EOF
}

# A PNG that decodes: signature, chunk CRCs, IHDR, and the inflated image
# data as long as height x (1 + width x bytes per pixel).
png_ok() {
  checks=$((checks + 1))
  python3 - "$1" <<'EOF' || fail "$1 is not a readable PNG"
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'signature'
pos, idat, ihdr = 8, b'', None
while pos < len(data):
    length, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + length]
    assert struct.unpack('>I', data[pos + 8 + length:pos + 12 + length])[0] == zlib.crc32(kind + body), 'crc'
    if kind == b'IHDR': ihdr = struct.unpack('>IIBBBBB', body)
    if kind == b'IDAT': idat += body
    pos += 12 + length
    if kind == b'IEND': break
width, height, depth, colour = ihdr[:4]
channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[colour]
assert width > 100 and height > 100, 'size'
assert len(zlib.decompress(idat)) == height * (1 + width * channels * depth // 8), 'image data'
EOF
}

# --- data: two small pairs cut from configs/data (every other point) ---------
awk '/^#/ || NR % 2 == 0' configs/data/volcano_moved.xyz >"$tmp/moved.xyz"   # ~2000 points, known motion
awk '/^#/ || NR % 3 == 0' configs/data/volcano_a.xyz >"$tmp/grid.xyz"        # ~1770 points
awk '/^#/ || NR % 2 == 1' configs/data/volcano_b.xyz >"$tmp/resampled.xyz"  # ~2000 points, not moved
matrix=$(sed -n 's/^# reference_from_moving: //p' configs/data/volcano_moved.xyz)
cat >"$tmp/sweep.yaml" <<EOF
pairs:
  - {name: moved, reference: $tmp/grid.xyz, moving: $tmp/moved.xyz, truth: {matrix: $matrix}}
  - {name: resampled, reference: $tmp/grid.xyz, moving: $tmp/resampled.xyz,
     truth: {rotation_deg: [0, 0, 0], translation: [0, 0, 0]}}
settings: {cost: axial, max_iterations: 40, covariance: false}
sweep:
  trust_region: [levenberg_marquardt, dogleg]
  loss: [none, cauchy]
perturbations: {rotation_deg: [1, 3], shift_spacings: [2, 5], directions: 3, seed: 5}
output: $tmp/full.csv
EOF
runs=48  # 2 pairs x 4 settings x 2 magnitudes x 3 directions

# --- the whole grid -------------------------------------------------------------
run sweep --config "$tmp/sweep.yaml" --jobs=2
if [[ $rc -ne 0 ]]; then
  fail "sweep: exit $rc"
else
  checks=$((checks + 1))
  [[ $(($(wc -l <"$tmp/full.csv") - 1)) -eq $runs ]] || fail "full.csv: expected $runs rows"
  [[ ! -e "$tmp/full.csv.partial" ]] || fail "the partial file was not removed"
  grep -q '^| 4 | ' "$tmp/full_summary.md" || fail "the summary does not rank 4 settings"
  grep -q '^| rank | setting | trust_region | loss |' "$tmp/stdout" || fail "no ranking on stdout"
  if has_part plots; then
    for plot in basin error_time translation_time; do png_ok "$tmp/full_$plot.png"; done
  fi
fi

# --- 3 shards in parallel, merged -------------------------------------------------
shard() { "$bin" sweep --config "$tmp/sweep.yaml" --jobs=1 --shard="$1/3" --output="$tmp/shard$1.csv" 2>/dev/null; }
if command -v parallel >/dev/null; then
  export -f shard
  export bin tmp
  parallel --will-cite shard ::: 1 2 3 || fail "a shard failed (GNU parallel)"
else
  for k in 1 2 3; do shard "$k" || fail "shard $k failed"; done
fi
run merge "$tmp/merged.csv" "$tmp/shard3.csv" "$tmp/shard1.csv" "$tmp/shard2.csv"
[[ $rc -eq 0 ]] || fail "merge: exit $rc"
same_rows "$tmp/merged.csv" "$tmp/full.csv"
checks=$((checks + 1))
[[ $(($(wc -l <"$tmp/shard2.csv") - 1)) -eq $((runs / 3)) ]] || fail "shard 2 should hold $((runs / 3)) rows"
# --resume on the merged CSV runs nothing and makes the ranking and plots.
cp "$tmp/merged.csv" "$tmp/merged_before.csv"
run sweep --config "$tmp/sweep.yaml" --output="$tmp/merged.csv" --resume
checks=$((checks + 1))
[[ $rc -eq 0 ]] && cmp -s "$tmp/merged.csv" "$tmp/merged_before.csv" &&
  { ! has_part plots || [[ -s "$tmp/merged_basin.png" ]]; } &&
  grep -q "$runs of $runs runs already done" "$tmp/stderr" || fail "resume of a complete CSV"

# --- killed part-way, then resumed ---------------------------------------------------
"$bin" sweep --config "$tmp/sweep.yaml" --jobs=1 --output="$tmp/killed.csv" 2>/dev/null &
pid=$!
for _ in $(seq 600); do  # until 6 rows are streamed (at most 60 s)
  [[ -f "$tmp/killed.csv.partial" && $(grep -c '^[0-9]' "$tmp/killed.csv.partial") -ge 6 ]] && break
  sleep 0.1
done
kill "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
checks=$((checks + 1))
if [[ -e "$tmp/killed.csv" || ! -e "$tmp/killed.csv.partial" ]]; then
  fail "the sweep was not interrupted part-way (finished too early?)"
else
  kept=$(grep -c '^[0-9]' "$tmp/killed.csv.partial")  # the settings comment and header aside
  expect_error "add --resume" sweep --config "$tmp/sweep.yaml" --output="$tmp/killed.csv"
  printf '999,torn' >>"$tmp/killed.csv.partial"  # a row cut off by the kill
  run sweep --config "$tmp/sweep.yaml" --output="$tmp/killed.csv" --resume --jobs=2
  [[ $rc -eq 0 ]] || fail "resume: exit $rc"
  grep -q "$kept of $runs runs already done" "$tmp/stderr" || fail "resume did not keep the $kept rows"
  same_rows "$tmp/killed.csv" "$tmp/full.csv"
fi

# --- align --manifest, sharded and merged ----------------------------------------------
printf 'reference,moving,output\n%s,%s,%s\n%s,%s,%s\n%s,%s,%s\n' \
  "$tmp/grid.xyz" "$tmp/moved.xyz" "$tmp/t0.json" "$tmp/grid.xyz" "$tmp/resampled.xyz" "$tmp/t1.json" \
  "$tmp/grid.xyz" "$tmp/moved.xyz" "$tmp/t2.json" >"$tmp/pairs.csv"
run align --manifest="$tmp/pairs.csv" --cost=axial --covariance=false --output="$tmp/batch.csv"
checks=$((checks + 1))
[[ $rc -eq 0 && -s "$tmp/t0.json" && -s "$tmp/t1.json" && -s "$tmp/t2.json" ]] || fail "manifest: exit $rc or a missing transform"
grep -q '"matrix"' "$tmp/t2.json" || fail "t2.json has no matrix"
for k in 1 2; do
  run align --manifest="$tmp/pairs.csv" --cost=axial --covariance=false --shard="$k/2" --output="$tmp/batch$k.csv"
done
run merge "$tmp/batch_merged.csv" "$tmp/batch1.csv" "$tmp/batch2.csv"
same_rows "$tmp/batch_merged.csv" "$tmp/batch.csv"
# Small pairs align side by side, one thread each: the same rows (times
# aside) on 1 and 4 threads; a row that fails in the middle is reported and
# the others go on.
printf '1 2 3\nnot a point\n' >"$tmp/bad.xyz"
printf 'reference,moving,output\n%s,%s,%s\n%s,%s,%s\n%s,%s,%s\n%s,%s,%s\n' \
  "$tmp/grid.xyz" "$tmp/moved.xyz" "$tmp/m0.json" "$tmp/grid.xyz" "$tmp/bad.xyz" "$tmp/m1.json" \
  "$tmp/grid.xyz" "$tmp/resampled.xyz" "$tmp/m2.json" "$tmp/resampled.xyz" "$tmp/moved.xyz" "$tmp/m3.json" \
  >"$tmp/mixed.csv"
for t in 1 4; do
  expect_error "1 of 4 pairs failed" align --manifest="$tmp/mixed.csv" --cost=axial --covariance=false \
    --threads=$t --output="$tmp/mixed$t.csv"
  grep -qF "pair 2/4 (row 1): error: $tmp/mixed.csv:3: column 'moving': $tmp/bad.xyz:2" "$tmp/stderr" || fail "manifest on $t threads: row 1's error"
done
same_rows "$tmp/mixed1.csv" "$tmp/mixed4.csv"
checks=$((checks + 1))
[[ $(grep -c ',converged' "$tmp/mixed4.csv") -eq 3 && -s "$tmp/m3.json" && ! -e "$tmp/m1.json" ]] ||
  fail "manifest on 4 threads: not 3 pairs aligned and 1 failed"
printf 'reference,moving,output\n%s,%s,%s\n' "$tmp/grid.xyz" "$tmp/moved.xyz" "$tmp/t0.json" >"$tmp/dup.csv"
printf '%s,%s,%s\n' "$tmp/grid.xyz" "$tmp/moved.xyz" "$tmp/t0.json" >>"$tmp/dup.csv"
expect_error "dup.csv:3: column 'output'" align --manifest="$tmp/dup.csv"
printf 'reference,moving,output,weight\n' >"$tmp/extra.csv"
expect_error "extra.csv:1: unknown column 'weight'" align --manifest="$tmp/extra.csv"
expect_error "not both" align --manifest="$tmp/pairs.csv" a.xyz b.xyz
expect_error "terrain inputs and outputs" align --manifest="$tmp/pairs.csv" --lod=0.5

# --- errors -----------------------------------------------------------------------------
expect_error "missing --config" sweep
sed 's/seed: 5/seed: 6/' "$tmp/sweep.yaml" >"$tmp/changed.yaml"
expect_error "run 0 in '$tmp/full.csv(.partial)' is not this config's run 0" \
  sweep --config "$tmp/changed.yaml" --resume
# The shard of another sweep (another seed: the same columns) is refused.
"$bin" sweep --config "$tmp/changed.yaml" --jobs=1 --shard=2/3 --output="$tmp/other2.csv" 2>/dev/null ||
  fail "the changed sweep's shard 2/3 failed"
expect_error "$tmp/other2.csv: run 1 is of another sweep (fingerprint" \
  merge "$tmp/m.csv" "$tmp/shard1.csv" "$tmp/other2.csv"
expect_error "flag '--output' expects a file name ending in .csv" sweep --config "$tmp/sweep.yaml" --output="$tmp/x.txt"
expect_error "flag '--shard' expects K/N" sweep --config "$tmp/sweep.yaml" --shard=4/3
printf 'pairs: [{reference: a, moving: b}]\nsettings: {cots: axial}\noutput: o.csv\n' >"$tmp/bad.yaml"
expect_error "bad.yaml:2: key 'settings.cots': unknown key 'cots' (did you mean 'cost'?)" sweep --config "$tmp/bad.yaml"
sed 's/^run_id,/id,/' "$tmp/full.csv" >"$tmp/other.csv"
expect_error "header differs" merge "$tmp/m.csv" "$tmp/full.csv" "$tmp/other.csv"
# `columns` under settings reads the pairs as align does: a wide CSV pair
# (x, y, z in columns 2-4 of 5) is the .xyz pair; sweeping it is refused.
for f in grid moved; do
  awk '!/^#/ && NF { print NR "," $1 "," $2 "," $3 ",7" }' "$tmp/$f.xyz" >"$tmp/${f}_wide.csv"
done
cat >"$tmp/columns.yaml" <<EOF
pairs:
  - {name: moved, reference: $tmp/grid_wide.csv, moving: $tmp/moved_wide.csv, truth: {matrix: $matrix}}
settings: {cost: axial, max_iterations: 40, covariance: false, columns: "2,3,4"}
perturbations: {rotation_deg: [1], shift_spacings: [2], directions: 1, seed: 5}
output: $tmp/columns.csv
EOF
run sweep --config "$tmp/columns.yaml" --jobs=1
checks=$((checks + 1))
[[ $rc -eq 0 && $(($(wc -l <"$tmp/columns.csv") - 1)) -eq 1 ]] && grep -q ',true,converged_improved,' "$tmp/columns.csv" ||
  fail "a sweep with settings.columns: expected one successful run ($(tail -1 "$tmp/columns.csv" 2>/dev/null | head -c 300))"
printf 'pairs: [{reference: a.las, moving: b.las}]\nsweep: {classes: [2, "2,9"]}\noutput: o.csv\n' >"$tmp/swept.yaml"
expect_error "swept.yaml:2: key 'sweep.classes': cannot be swept: it decides how the pairs are read (once); set it under 'settings:'" \
  sweep --config "$tmp/swept.yaml"
sed '2s/,moved,/,other,/' "$tmp/full.csv" >"$tmp/conflict.csv"
expect_error "run_id 0 appears twice" merge "$tmp/m.csv" "$tmp/full.csv" "$tmp/conflict.csv"
run merge "$tmp/m.csv" "$tmp/full.csv" "$tmp/full.csv"  # identical duplicates are fine
[[ $rc -eq 0 ]] && cmp -s "$tmp/m.csv" "$tmp/full.csv" || fail "merging a file with itself"
expect_error "expected OUT.csv and at least one IN.csv" merge "$tmp/m.csv"

echo "$checks checks, $failures failures"
[[ $failures -eq 0 ]]

#!/usr/bin/env bash
# One test per row of the "Bad input" table (docs/formats.md): every class of bad
# input gives exit code 2, exactly one line on stderr naming the file (and
# line) or the config key, and no output file; the two classes surfreg
# accepts (duplicate xy samples, coordinates near 1e7) give the right numbers.
# Then what the command line must survive (issue 23): outputs that cannot be
# written (a file-size limit, a full device), SIGINT and SIGTERM during
# measure, align and sweep, a resume with other settings, a merge into one
# of its inputs, --jobs=0, and a failed verdict (exit 3).
# Usage: cli_bad_input_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
data=$(realpath -- "$(dirname -- "$(realpath -- "$0")")/../configs/data") || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 2
out=$tmp/out
mkdir "$out"
failures=0
checks=0

# expect_error TEXT ARGS...: exit 2, one line on stderr containing TEXT, nothing in out/.
expect_error() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $(wc -l <stderr) -ne 1 ]]; then
    fail "surfreg $*: expected exactly one line on stderr"
  elif ! grep -qF -- "$text" stderr; then
    fail "surfreg $*: stderr does not mention '$text'"
  elif [[ -n $(ls -A "$out") ]]; then
    fail "surfreg $*: wrote $(ls -A "$out")"
  fi
}

# json_value KEY: a number from the JSON on stdout.
json_value() {
  python3 -c 'import json, sys; print(repr(json.load(open("stdout"))[sys.argv[1]]))' "$1"
}

# The inputs: a good 104-point surface on the unit square and one bad file per class.
python3 - <<'EOF' || exit 2
import random, struct
random.seed(7)
pts = [(random.random(), random.random(), random.random()) for _ in range(100)]
pts += [(0, 0, 0.5), (1, 0, 0.5), (0, 1, 0.5), (1, 1, 0.5)]
def xyz(name, points, fmt="%.9f %.9f %.9f\n"):
    with open(name, "w") as f:
        f.write("".join(fmt % p for p in points))
xyz("good.xyz", pts)
open("empty.xyz", "w").close()
xyz("one.xyz", pts[:1])
xyz("two.xyz", pts[:2])
xyz("collinear.xyz", [(t, 2 * t + 1, t * t) for t in range(50)])
# On y = 2x only up to the decimal rounding of 0.01 i (issue 23's case).
xyz("rounded_line.xyz", [(0.01 * i, 0.02 * i, 1.0) for i in range(100)], "%.17g %.17g %.17g\n")
with open("nan_x.xyz", "w") as f: f.write("0 0 0\nnan 0 1\n0 1 0\n1 1 1\n")
with open("nan_y.xyz", "w") as f: f.write("0 0 0\n1 NaN 1\n0 1 0\n1 1 1\n")
with open("inf_z.xyz", "w") as f: f.write("0 0 0\n1 0 1\n0 1 -inf\n1 1 1\n")
with open("cut_short.xyz", "w") as f: f.write("0 0 0\n1 0 1\n0 1 0\n1 1")
header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
          "property float x\nproperty float y\nproperty float z\nend_header\n")
body = b"".join(struct.pack("<fff", *p) for p in pts)
with open("truncated.ply", "wb") as f: f.write((header % len(pts)).encode() + body[: len(body) // 2 + 5])
with open("more_declared.ply", "wb") as f: f.write((header % (len(pts) + 20)).encode() + body)
with open("fewer_declared.ply", "wb") as f: f.write((header % (len(pts) - 20)).encode() + body)
ascii_header = header.replace("binary_little_endian", "ascii")
with open("fewer_declared_ascii.ply", "w") as f:
    f.write(ascii_header % 50 + "".join("%.6f %.6f %.6f\n" % p for p in pts))
# the same xy twice with different heights: merged, heights averaged
xyz("duplicates.xyz", pts + [(pts[3][0], pts[3][1], pts[3][2] + 1.0)])
xyz("far.xyz", [(x + 10, y, z) for x, y, z in pts])
xyz("sliver.xyz", [(x + 0.99999, y, z) for x, y, z in pts])
# UTM-sized coordinates with sub-millimetre detail, and the same pair near 0
xyz("big_a.xyz", [(5e5 + 10 * x, 1e7 + 10 * y, 100 + z) for x, y, z in pts], "%.5f %.5f %.5f\n")
xyz("big_b.xyz", [(5e5 + 10 * x + 3e-4, 1e7 + 10 * y, 100 + z + 5e-4) for x, y, z in pts],
    "%.5f %.5f %.5f\n")
xyz("zero_weights.xyz", [p + (0.0,) for p in pts], "%.9f %.9f %.9f %g\n")
xyz("small_a.xyz", [(10 * x, 10 * y, z) for x, y, z in pts], "%.5f %.5f %.5f\n")
xyz("small_b.xyz", [(10 * x + 3e-4, 10 * y, z + 5e-4) for x, y, z in pts], "%.5f %.5f %.5f\n")
EOF

# --- surface files ---
expect_error "empty.xyz: no points" measure empty.xyz good.xyz
expect_error "one.xyz: 1 point" measure one.xyz good.xyz
expect_error "two.xyz: 2 points" measure good.xyz two.xyz
expect_error "collinear.xyz: all points lie on one line" measure collinear.xyz good.xyz
expect_error "rounded_line.xyz: all points lie on one line in xy" measure good.xyz rounded_line.xyz
expect_error "nan_x.xyz:2: x is NaN" measure nan_x.xyz good.xyz
expect_error "nan_y.xyz:2: y is NaN" measure nan_y.xyz good.xyz
expect_error "inf_z.xyz:3: z is infinite" measure inf_z.xyz good.xyz
expect_error "cut_short.xyz:4:" measure cut_short.xyz good.xyz
expect_error "truncated.ply: file ends after 52 of 104 vertices" measure truncated.ply good.xyz
expect_error "more_declared.ply: file ends after 104 of 124 vertices" measure more_declared.ply good.xyz
expect_error "fewer_declared.ply: 240 bytes of data after the 84 vertices" measure fewer_declared.ply good.xyz
expect_error "fewer_declared_ascii.ply:58: a line of data after the 50 vertices" \
  measure fewer_declared_ascii.ply good.xyz
expect_error "far.xyz and good.xyz do not overlap" measure far.xyz good.xyz
expect_error "sliver.xyz and good.xyz overlap only in a sliver" measure sliver.xyz good.xyz
expect_error "missing.xyz: cannot open" measure missing.xyz good.xyz
# measure's keys are the library's table (measure/measure_keys.h): its messages.
expect_error "flag '--volume' expects one of overlay, union, got 'uni'" measure good.xyz good.xyz --volume=uni
expect_error "flag '--threads' expects an integer >= 1, or all, got '0'" measure good.xyz good.xyz --threads=0
expect_error "flag '--min_overlap_fraction' expects a number in [0, 1], got '2'" \
  measure good.xyz good.xyz --min_overlap_fraction=2

# Duplicate xy with different heights: accepted, heights averaged, counted and warned about.
run measure duplicates.xyz good.xyz --json
if [[ $rc -ne 0 ]] || [[ $(json_value n_duplicates_a) != 1 ]] ||
    ! grep -q "^surfreg: warning: duplicates.xyz: 1 sample" stderr; then
  fail "duplicates: expected exit 0, n_duplicates_a = 1 and a warning"
fi

# Coordinates near 1e7 with sub-millimetre detail: the same numbers as near 0.
run measure big_a.xyz big_b.xyz --json
big=$(json_value rho_d)
run measure small_a.xyz small_b.xyz --json
small=$(json_value rho_d)
if ! python3 -c "import sys; b, s = map(float, sys.argv[1:]); sys.exit(not (s > 0 and abs(b - s) <= 1e-6 * s))" \
    "$big" "$small"; then
  fail "coordinates near 1e7: rho_d $big differs from $small near 0"
fi

# A mask polygon outside the data: verdict failed, exit 3, the JSON still
# written, warnings in the program's own format (not glog's; the solver's
# own complaints come first), and the wide search the failure calls for
# announced as it begins.
printf '100 100\n101 100\n101 101\n100 101\n' >far.poly
run align good.xyz good.xyz --mask=far.poly --output=out/failed.json
if [[ $rc -ne 3 ]] || ! grep -q '"verdict": "failed"' out/failed.json 2>/dev/null; then
  fail "mask outside the data: expected exit 3 and the JSON with verdict failed"
elif grep -v '^align: wide search ' stderr | grep -qv '^surfreg: warning: ' ||
     ! grep -q '^surfreg: warning: align: failed: ' stderr; then
  fail "mask outside the data: expected only 'surfreg: warning: ...' lines, one 'align: failed: ...'"
elif [[ $(grep -c '^align: wide search (the first solve did not improve)' stderr) -ne 1 ]]; then
  fail "mask outside the data: expected the wide search announced once"
fi
rm -f out/failed.json

# --- configs and options ---
# Usage mistakes: the error line with the suggestion, then the usage hint
# (--jobs=0 is with the sweep below).
for mistake in "aling good.xyz good.xyz|unknown command 'aling' (did you mean 'align'?)" \
               "align good.xyz good.xyz --max_iter=5|unknown flag '--max_iter=5' (did you mean '--max_iterations'?)"; do
  # shellcheck disable=SC2086  # the command's words
  run ${mistake%%|*}
  if [[ $rc -ne 2 ]] || [[ "$(head -1 stderr)" != "surfreg: error: ${mistake#*|}" ]] ||
     [[ "$(sed -n 2p stderr)" != "run 'surfreg help' for usage" ]] || [[ $(wc -l <stderr) -ne 2 ]]; then
    fail "surfreg ${mistake%%|*}: expected exit 2, 'surfreg: error: ${mistake#*|}' and the usage hint"
  fi
done
printf 'reference: good.xyz\nmoving: good.xyz\ncostt: axial\n' >unknown_key.yaml
expect_error "unknown_key.yaml:3: unknown key 'costt' (did you mean 'cost'?)" align --config unknown_key.yaml
printf 'reference: good.xyz\nmoving: good.xyz\nmax_iterations: many\n' >wrong_type.yaml
expect_error "wrong_type.yaml:3: key 'max_iterations' expects an integer" align --config wrong_type.yaml
printf 'reference: good.xyz\nmoving: nothere.xyz\n' >missing_file.yaml
expect_error "missing_file.yaml:2: key 'moving': nothere.xyz: cannot open" align --config missing_file.yaml
expect_error "missing.yaml: cannot open" align --config missing.yaml
expect_error "flag '--max_iterations'" align good.xyz good.xyz --max_iterations=-3
expect_error "weight per_point needs per-sample weights on the reference, but good.xyz has none" \
  align good.xyz good.xyz --weights=per_point
expect_error "every weight of zero_weights.xyz is 0" align zero_weights.xyz good.xyz --weights=per_point

# A rotation that folds the moving surface over in xy.
expect_error "the initial motion folds" align good.xyz good.xyz --initial_rotation_deg=0,150,0 \
  --output="$out/t.json"

# An output in a directory that does not exist.
expect_error "directory '$tmp/nowhere' does not exist" align good.xyz good.xyz \
  --output="$tmp/nowhere/t.json"

# --- outputs that cannot be written ---
# Past a file-size limit (`ulimit -f`, which without surfreg's handling kills
# the process with SIGXFSZ) and to a full device (/dev/full as stdout): exit
# 2 and one line "surfreg: error: ..." naming the file (or the standard
# output), and no file and no temporary left behind.
# limited KIB EXPECTED_FILE ARGS...: runs the command under `ulimit -f KIB`
# and checks exit 2, one error line naming EXPECTED_FILE, and an empty out/.
limited() {
  local kib=$1 file=$2
  shift 2
  rm -rf "$out" && mkdir "$out"
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
  elif [[ -n "$(ls -A "$out")" ]]; then
    fail "ulimit -f $kib: $*: files left behind: $(ls -A "$out")"
  fi
}

limited 1 out/log.csv align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --log="$tmp/out/log.csv"
limited 1 out/run.json align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --output="$tmp/out/run.json"
limited 4 out/aligned.xyz align "$data/volcano_a.xyz" "$data/volcano_moved.xyz" --aligned="$tmp/out/aligned.xyz"
if has_part gdal; then  # rasters: not in a build without GDAL
  limited 4 out/dod.tif align "$data/volcano_dem.tif" "$data/volcano_dem_moved.tif" --output="$tmp/out/dod.tif"
  has_part plots &&
    limited 4 out/dod.png align "$data/volcano_dem.tif" "$data/volcano_dem_moved.tif" --dod_png="$tmp/out/dod.png"
fi
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

rm -rf "$out" && mkdir "$out"

# --- SIGINT and SIGTERM ---
# Each signalled command ends with exit 130 (SIGINT) / 143 (SIGTERM) and
# "surfreg: interrupted" as its last and only non-progress line on stderr,
# leaves no temporary file, and keeps what is complete: align's --log rows
# so far, the sweep's partial file, which --resume then continues to the
# uninterrupted sweep's rows.
# Two wavy 400 x 400 grids, the second shifted and tilted: seconds of work.
python3 - <<'PY' || exit 2
import math
def grid(name, dx, dz, tilt):
    with open(name, "w") as f:
        for i in range(400):
            for j in range(400):
                x, y = i * 0.05, j * 0.05
                z = math.sin(x) * math.cos(0.7 * y) + 0.1 * x + tilt * y + dz
                f.write("%.6f %.6f %.6f\n" % (x + dx, y, z))
grid("a.xyz", 0, 0, 0)
grid("b.xyz", 0.07, 0.2, 0.01)
PY

# start ARGS...: the command in the background, its pid in `pid`.
start() {
  checks=$((checks + 1))
  # Emptied first: the background command's own redirection may come after
  # wait_for's first look, which would then match the previous run's lines.
  : >stdout
  : >stderr
  "$bin" "$@" >stdout 2>stderr &
  pid=$!
}

# wait_for FILE PATTERN: until FILE has a line matching PATTERN (60 s at most).
wait_for() {
  for _ in $(seq 600); do
    grep -q -- "$2" "$1" 2>/dev/null && return 0
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}

# finish SIGNAL CODE WHAT: signal the running command; check the exit code,
# the last stderr line, that no other line is an error, and no temporary.
finish() {
  kill -"$1" "$pid"
  wait "$pid"
  rc=$?
  if [[ $rc -ne $2 ]]; then
    fail "$3: expected exit $2 after SIG$1"
  elif [[ $(tail -n 1 stderr) != "surfreg: interrupted" ]]; then
    fail "$3: the last line on stderr is not 'surfreg: interrupted'"
  elif [[ $(grep -c '^surfreg: ' stderr) -ne 1 ]]; then
    fail "$3: more than one surfreg: line on stderr"
  elif [[ -n $(find . -name '*.tmp-*') ]]; then
    fail "$3: temporary files left: $(find . -name '*.tmp-*')"
  fi
}

# --- measure: signalled while it reads or measures ---------------------------------
start measure a.xyz b.xyz --json
sleep 0.3
kill -0 "$pid" 2>/dev/null || fail "measure finished within 0.3 s: too fast to interrupt"
finish INT 130 "measure"
[[ -s stdout ]] && fail "measure: printed a report although interrupted"

# --- align: the --log rows so far are kept -------------------------------------------
start align a.xyz b.xyz --cost=volume --levels=1 --max_iterations=500 --function_tolerance=1e-30 \
  --progress --log=out/log.csv --output=out/t.json --aligned=out/aligned.xyz
wait_for stderr "volume iteration *3 " || fail "align: no progress line within 60 s"
finish INT 130 "align"
checks=$((checks + 1))
rows=$(($(wc -l <out/log.csv 2>/dev/null || echo 0) - 1))
if [[ ! -s out/log.csv ]] || ! head -n 1 out/log.csv | grep -q '^level,start,cost_kind,iteration'; then
  fail "align: the --log CSV was not kept"
elif [[ $rows -lt 3 ]]; then
  fail "align: the --log CSV holds $rows rows, expected the iterations printed so far"
fi
[[ -e out/t.json || -e out/aligned.xyz ]] && fail "align: wrote outputs of an unfinished run"
rm -f out/*

# --- sweep: SIGTERM, then --resume gives the uninterrupted result ----------------------
mkdir sw
awk 'NR % 16 == 0' a.xyz >sa.xyz
awk 'NR % 16 == 1' b.xyz >sb.xyz
cat >sweep.yaml <<YAML
pairs:
  - {name: p, reference: sa.xyz, moving: sb.xyz}
settings: {cost: axial, max_iterations: 30, covariance: false, levels: 1}
sweep: {loss: [none, cauchy]}
perturbations: {rotation_deg: [1, 2], shift_spacings: [1, 2], directions: 3, seed: 3}
output: sw/full.csv
YAML
runs=12
run sweep --config sweep.yaml --jobs=2
[[ $rc -eq 0 ]] || fail "sweep: exit $rc"
start sweep --config sweep.yaml --jobs=1 --output=sw/cut.csv
wait_for sw/cut.csv.partial '^3,' || fail "sweep: run 3 was not streamed within 60 s"
finish TERM 143 "sweep"
checks=$((checks + 1))
if [[ -e sw/cut.csv || ! -e sw/cut.csv.partial ]]; then
  fail "sweep: expected the partial file and no CSV"
else
  kept=$(($(grep -c '^[0-9]' sw/cut.csv.partial)))
  # A resume with other settings than the partial file's: refused, naming the key.
  sed 's/max_iterations: 30/max_iterations: 10/' sweep.yaml >fewer.yaml
  expect_error "was written with other settings: max_iterations '30' there, '10' now" \
    sweep --config fewer.yaml --output=sw/cut.csv --resume
  run sweep --config sweep.yaml --output=sw/cut.csv --resume --jobs=2
  [[ $rc -eq 0 ]] || fail "sweep --resume: exit $rc"
  grep -q "$kept of $runs runs already done" stderr || fail "sweep --resume did not keep the $kept rows"
  checks=$((checks + 1))
  python3 - sw/cut.csv sw/full.csv <<'PY' || fail "the resumed sweep's rows differ from the uninterrupted ones"
import csv, sys
def rows(path):
    table = list(csv.reader(open(path, newline='')))
    drop = table[0].index('seconds')
    return [r[:drop] + r[drop + 1:] for r in table]
sys.exit(rows(sys.argv[1]) != rows(sys.argv[2]))
PY
fi

# --- sweep and merge mistakes ---
cp sw/cut.csv sw/cut_before.csv
expect_error "argument OUT: 'sw/cut.csv' is also input 2 ('sw/cut.csv'); write the merge to another file" \
  merge sw/cut.csv sw/full.csv sw/cut.csv
checks=$((checks + 1))
cmp -s sw/cut.csv sw/cut_before.csv || fail "merge into one of its inputs changed it"
expect_error "flag '--jobs' expects an integer >= 1, got 0" sweep --config sweep.yaml --jobs=0

if [[ $failures -ne 0 ]]; then
  echo "$failures failure(s) in $checks checks"
  exit 1
fi
echo "all $checks bad-input checks passed"

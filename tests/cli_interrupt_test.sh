#!/usr/bin/env bash
# SIGINT and SIGTERM during long runs (issue 23): `measure`, `align` with a
# --log and `sweep` are signalled once they are under way; each must end with
# exit 130 (SIGINT) / 143 (SIGTERM) and "surfreg: interrupted" as its last
# and only non-progress line on stderr, leave no temporary file, and keep
# what is complete: align's --log rows so far, the sweep's partial file,
# which --resume then continues to the uninterrupted sweep's rows.
# Usage: cli_interrupt_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 2
mkdir out
failures=0
checks=0

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

# --- sweep: SIGTERM, then --resume gives the uninterrupted result ----------------------
awk 'NR % 16 == 0' a.xyz >sa.xyz
awk 'NR % 16 == 1' b.xyz >sb.xyz
cat >sweep.yaml <<YAML
pairs:
  - {name: p, reference: sa.xyz, moving: sb.xyz}
settings: {cost: axial, max_iterations: 30, covariance: false, levels: 1}
sweep: {loss: [none, cauchy]}
perturbations: {rotation_deg: [1, 2], shift_spacings: [1, 2], directions: 3, seed: 3}
output: out/full.csv
YAML
runs=12
run sweep --config sweep.yaml --jobs=2
[[ $rc -eq 0 ]] || fail "sweep: exit $rc"
start sweep --config sweep.yaml --jobs=1 --output=out/cut.csv
wait_for out/cut.csv.partial '^3,' || fail "sweep: run 3 was not streamed within 60 s"
finish TERM 143 "sweep"
checks=$((checks + 1))
if [[ -e out/cut.csv || ! -e out/cut.csv.partial ]]; then
  fail "sweep: expected the partial file and no CSV"
else
  kept=$(($(grep -c '^[0-9]' out/cut.csv.partial)))
  run sweep --config sweep.yaml --output=out/cut.csv --resume --jobs=2
  [[ $rc -eq 0 ]] || fail "sweep --resume: exit $rc"
  grep -q "$kept of $runs runs already done" stderr || fail "sweep --resume did not keep the $kept rows"
  checks=$((checks + 1))
  python3 - out/cut.csv out/full.csv <<'PY' || fail "the resumed sweep's rows differ from the uninterrupted ones"
import csv, sys
def rows(path):
    table = list(csv.reader(open(path, newline='')))
    drop = table[0].index('seconds')
    return [r[:drop] + r[drop + 1:] for r in table]
sys.exit(rows(sys.argv[1]) != rows(sys.argv[2]))
PY
fi

echo "$checks checks, $failures failures"
[[ $failures -eq 0 ]]

#!/usr/bin/env bash
# End-to-end test of `surfreg series`: the shipped example
# configs/series_volcano.yaml on configs/data/series/ against its truth
# (every epoch within 0.1° and 0.5 m, the reference's matrix the identity),
# the positional form and flags giving the same answer, the aligned epochs,
# given pairs, and bad input (exit 2, one line on stderr, no output written).
# Usage: cli_series_test.sh SURFREG_BINARY (needs python3, standard library).
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run, expect_refused
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
data=configs/data/series

# check_truth JSON REFERENCE: every epoch's matrix against truth.json, relative to REFERENCE.
check_truth() {
  checks=$((checks + 1))
  if ! python3 - "$1" "$2" "$data/truth.json" <<'PY'; then
import json, math, sys
series, reference, truth = json.load(open(sys.argv[1])), int(sys.argv[2]), json.load(open(sys.argv[3]))
def mat(v): return [v[4 * i:4 * i + 4] for i in range(4)]
def mul(a, b): return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]
def inv(m):  # rigid
    r = [[m[j][i] for j in range(3)] for i in range(3)]
    t = [-sum(r[i][k] * m[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [t[0]], r[1] + [t[1]], r[2] + [t[2]], [0, 0, 0, 1]]
world = [mat(w) for w in truth["world_from_epoch"]]
bad = 0
for k, e in enumerate(series["epochs"]):
    want = mul(inv(world[reference]), world[k])
    got = e["matrix"]
    r = mul(got, inv(want))
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1) / 2))))
    c = e["centre"] + [1]
    shift = math.dist([sum(got[i][j] * c[j] for j in range(4)) for i in range(3)],
                      [sum(want[i][j] * c[j] for j in range(4)) for i in range(3)])
    if angle > 0.1 or shift > 0.5 or e["verdict"] != "converged_improved":
        print("epoch %d: %.4f deg, %.4f m, %s" % (k, angle, shift, e["verdict"]))
        bad += 1
if series["epochs"][reference]["matrix"] != [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]:
    print("the reference's matrix is not the identity"); bad += 1
sys.exit(1 if bad else 0)
PY
    fail "series $1: epochs against the truth"
  fi
}

# --- the example config ---
run series --config configs/series_volcano.yaml --output="$tmp/series.json" --quiet
[[ $rc -eq 0 ]] || fail "series example: exit code"
check_truth "$tmp/series.json" 0
grep -q "^epoch 3: .*converged_improved" "$tmp/stdout" || fail "series example: summary lines"

# --- positional, another reference, aligned epochs, JSON on stdout ---
mkdir "$tmp/aligned"
run series $data/e0.xyz $data/e1.xyz $data/e2.xyz $data/e3.xyz --reference=2 --aligned_dir="$tmp/aligned" --json
[[ $rc -eq 0 ]] || fail "series positional: exit code"
cp "$tmp/stdout" "$tmp/positional.json"
check_truth "$tmp/positional.json" 2
for k in 0 1 2 3; do
  [[ -s $tmp/aligned/e$k.xyz ]] || fail "series --aligned_dir: e$k.xyz not written"
done
# The aligned epoch 2 is the reference itself: its points unchanged.
checks=$((checks + 1))
python3 - "$tmp/aligned/e2.xyz" "$data/e2.xyz" <<'PY' || fail "series --aligned_dir: the reference epoch moved"
import sys
def points(path):
    return [tuple(float(v) for v in l.split()[:3]) for l in open(path) if l.strip() and not l.startswith("#")]
a, b = points(sys.argv[1]), points(sys.argv[2])
sys.exit(0 if len(a) == len(b) and max(max(abs(p - q) for p, q in zip(u, v)) for u, v in zip(a, b)) < 1e-3 else 1)
PY

# --- given pairs: only those are aligned ---
run series $data/e0.xyz $data/e1.xyz $data/e2.xyz --pairs=0-1,1-2 --json
[[ $rc -eq 0 ]] || fail "series --pairs: exit code"
checks=$((checks + 1))
python3 -c 'import json,sys; p=json.load(open(sys.argv[1]))["pairs"]; sys.exit(0 if [(q["reference"], q["moving"]) for q in p] == [(0, 1), (1, 2)] else 1)' \
  "$tmp/stdout" || fail "series --pairs: the pairs aligned"

# --- dates: the change between consecutive epochs per year ---
run series --config configs/series_volcano.yaml --dates=2020-05-01,2021-05-01,2023-05-01,2023-11-01 --output="$tmp/dated.json" --json --quiet
[[ $rc -eq 0 ]] || fail "series --dates: exit code"
checks=$((checks + 1))
python3 - "$tmp/stdout" <<'PY' || fail "series --dates: the consecutive changes' years and rates"
import json, sys
c = json.load(open(sys.argv[1]))["consecutive"]
years = [e["years"] for e in c]
ok = abs(years[0] - 365 / 365.25) < 1e-12 and abs(years[1] - 730 / 365.25) < 1e-12 and abs(years[2] - 184 / 365.25) < 1e-12
ok = ok and all(abs(e["net_volume_per_year"] * e["years"] - e["net_volume"]) <= 1e-9 * abs(e["net_volume"]) for e in c)
ok = ok and c[1]["from_date"] == "2021-05-01" and c[1]["to_date"] == "2023-05-01"
sys.exit(0 if ok else 1)
PY
expect_refused "flag '--dates': expects dates as YYYY-MM-DD, got '2021-02-30'" \
  series $data/e0.xyz $data/e1.xyz --dates=2020-05-01,2021-02-30
expect_refused "flag '--dates': 2019-02-03 is not after 2020-05-01 (the surfaces in time order)" \
  series $data/e0.xyz $data/e1.xyz --dates=2020-05-01,2019-02-03
expect_refused "flag '--dates': 1 dates for 2 surfaces (one per surface)" series $data/e0.xyz $data/e1.xyz --dates=2020-05-01

# --- bad input: one line, exit 2, nothing written ---
printf '1 2 3\n4 5 x\n' >"$tmp/bad.xyz"
expect_refused "$tmp/bad.xyz:2:" series $data/e0.xyz "$tmp/bad.xyz" --output="$tmp/bad.json"
[[ ! -e $tmp/bad.json ]] || fail "series bad input: output written"
: >"$tmp/empty.xyz"
expect_refused "$tmp/empty.xyz: no points" series $data/e0.xyz "$tmp/empty.xyz"
printf '1 2 nan\n3 4 5\n' >"$tmp/nan.xyz"
expect_refused "$tmp/nan.xyz:1: z is NaN" series $data/e0.xyz "$tmp/nan.xyz"
printf 'reference: 0\n' >"$tmp/nokey.yaml"
expect_refused "nokey.yaml: key 'surfaces': a series needs at least 2 surfaces, got 0" series --config "$tmp/nokey.yaml"
expect_refused "flag '--reference' expects an epoch index >= 0 or one of the surfaces, got ''" series $data/e0.xyz $data/e1.xyz --reference=
expect_refused "flag '--reference': epoch 5 is beyond the 2 epochs" series $data/e0.xyz $data/e1.xyz --reference=5
expect_refused "flag '--pairs': expects pairs of epoch indices such as 0-1, got '0:1'" series $data/e0.xyz $data/e1.xyz --pairs=0:1
expect_refused "flag '--pairs': 0-3 does not name two different epochs of the 2" series $data/e0.xyz $data/e1.xyz --pairs=0-3
expect_refused "no such file '$tmp/none.xyz'" series $data/e0.xyz "$tmp/none.xyz"
# Usage errors: the message, then the command's usage line.
expect_usage() {
  local text=$1
  shift
  run "$@"
  checks=$((checks + 1))
  if [[ $rc -ne 2 ]] || ! head -1 "$tmp/stderr" | grep -qF -- "$text" || ! grep -q "^usage: surfreg series" "$tmp/stderr"; then
    fail "surfreg $*: expected exit 2, then: $text, and the usage"
  fi
}
expect_usage "a series needs at least 2 epochs" series $data/e0.xyz
expect_usage "give either --config FILE.yaml or the epochs' files, not both" series --config configs/series_volcano.yaml $data/e0.xyz
# Epochs 0 and 3 share 0.45 of their footprints: with min_overlap 0.9 no pair is left.
expect_refused "overlaps no other by min_overlap 0.9" series $data/e0.xyz $data/e3.xyz --min_overlap=0.9
printf 'surfaces: [%s, %s]\ncots: volume\n' $data/e0.xyz $data/e1.xyz >"$tmp/typo.yaml"
expect_refused "typo.yaml:2: unknown key 'cots' (did you mean 'cost'?)" series --config "$tmp/typo.yaml"
expect_usage "flag '--dod' is not used by 'series'" series $data/e0.xyz $data/e1.xyz --dod="$tmp/d.tif"

echo "$checks checks, $failures failures"
[[ $failures -eq 0 ]]

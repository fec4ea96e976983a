#!/usr/bin/env bash
# A tiled measure in parts (issue 24): `surfreg measure --tile=N
# --shard=K/N --partial=P.json --dod=D.tif` for K = 1..N, joined by
# `surfreg merge OUT.json P*.json --dod=DOD.tif` (given in any order),
# gives the unsharded measure (every volume and area to 1e-9 relative, the
# counts exactly) and its DoD cell for cell, for 4 shards and for more
# shards than tile rows; a missing, repeated or foreign part is refused. A
# tiled run killed part-way (SIGKILL, then SIGTERM, once it reports
# progress) and resumed with --resume gives the uninterrupted run's outputs:
# the same measures (to 1e-9: a tile's two threads may split its overlay
# sums another way), the same DoD cells.
# Usage: cli_tiled_shard_test.sh SURFREG_BINARY   (needs python3, standard library)
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run, expect_refused
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
here=$(dirname -- "$(realpath -- "$0")")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 2
failures=0
checks=0
printf '1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n' >id.txt

# The measures of two --json documents: volumes and areas to 1e-9 relative,
# counts exactly.
same_measures() {
  python3 - "$@" <<'EOF'
import json, sys
u, t = (json.load(open(p)) for p in sys.argv[1:3])
for part in (lambda d: d, lambda d: d["change"]):
    for key, value in part(u).items():
        if isinstance(value, float):
            assert abs(value - part(t)[key]) <= 1e-9 * abs(value), (key, value, part(t)[key])
for key in ("n_overlap_nodes", "n_cells", "n_points_a", "n_points_b", "tiles", "frame", "file_a"):
    assert key not in u or u[key] == t[key], (key, u[key], t[key])
EOF
}

# The DoD cells of two GeoTIFFs (read back through `transform` by the
# identity, shortest round-trip digits): identical, nodata at the same cells.
same_dod() {
  "$bin" transform "$1" --transform=id.txt --output=one.xyz >/dev/null 2>&1 &&
    "$bin" transform "$2" --transform=id.txt --output=two.xyz >/dev/null 2>&1 &&
    cmp -s <(grep -v '^#' one.xyz) <(grep -v '^#' two.xyz) && [[ -s one.xyz ]]
}

python3 "$here/make_tiled_pair.py" || exit 2
run measure a.asc b.asc --json --tile=16 --dod=whole.tif --quiet
cp stdout whole.json
[[ $rc -eq 0 ]] || fail "unsharded tiled measure: exit $rc"
run measure a.asc b.asc --json --dod=untiled.tif --quiet
cp stdout untiled.json

# 4 shards (12 tile rows: bands of 3), and 13 (more than the rows: one is
# empty), merged in a shuffled order.
for shards in 4 13; do
  rm -f p*.json d*.tif
  for ((k = 1; k <= shards; k++)); do
    run measure a.asc b.asc --tile=16 --shard=$k/$shards --partial=p$k.json --dod=d$k.tif --quiet
    [[ $rc -eq 0 ]] || fail "--shard=$k/$shards: exit $rc: $(cat stderr)"
  done
  [[ ! -e p1.json.resume ]] || fail "--shard: the state directory was left behind"
  parts=$(ls p*.json | sort -r)
  # shellcheck disable=SC2086
  run merge merged.json $parts --dod=merged.tif --json
  [[ $rc -eq 0 ]] || fail "merge of $shards shards: exit $rc: $(cat stderr)"
  checks=$((checks + 1))
  same_measures whole.json merged.json || fail "$shards shards merged differ from the unsharded run"
  checks=$((checks + 1))
  same_measures untiled.json merged.json || fail "$shards shards merged differ from the untiled run"
  checks=$((checks + 1))
  cmp -s stdout merged.json || fail "merge --json: stdout is not OUT.json"
  checks=$((checks + 1))
  same_dod untiled.tif merged.tif || fail "the DoD of $shards shards differs from the untiled one"
done
# The change budget (σ numbers) in 4 shards: the merge gives the unsharded budget.
sigma=(--sigma_reference=0.05 --sigma_moving=0.08 --lod_confidence=0.9)
run measure a.asc b.asc --json --tile=16 "${sigma[@]}" --quiet
cp stdout budget_whole.json
rm -f s*.json
for k in 1 2 3 4; do
  run measure a.asc b.asc --tile=16 --shard=$k/4 --partial=s$k.json "${sigma[@]}" --quiet
  [[ $rc -eq 0 ]] || fail "budget --shard=$k/4: exit $rc"
done
run merge budget_merged.json s4.json s2.json s1.json s3.json --json
checks=$((checks + 1))
python3 - budget_whole.json budget_merged.json <<'PY' || fail "4 shards: the merged change budget differs"
import json, sys
u, t = (json.load(open(p))["change"]["uncertainty"] for p in sys.argv[1:3])
assert u["cut_nodes"] > 1000 and u["lod_confidence"] == 0.9, u
for key, value in u.items():
    if isinstance(value, str) or key.endswith("nodes"):
        assert t[key] == value, (key, value, t[key])
    else:
        assert abs(t[key] - value) <= 1e-9 * max(abs(value), 1.0), (key, value, t[key])
PY
run measure a.asc b.asc --tile=16 --shard=2/4 --partial=other.json --sigma_reference=0.5 --quiet
expect_refused "a part of another measure" merge out.json s1.json other.json s3.json s4.json

run merge text.json p3.json p1.json p2.json p4.json p5.json p6.json p7.json p8.json p9.json \
  p10.json p11.json p12.json p13.json
checks=$((checks + 1))
grep -q "^tiles: .*180 of 16 x 16 cells" stdout || fail "merge: no text report on stdout"

# Refused, one line each.
expect_refused "merge: part 2/13 is missing" merge out.json p1.json p3.json p4.json
expect_refused "merge: part 3/13 is given twice" merge out.json p1.json p2.json p3.json p3.json
expect_refused "argument OUT: 'p2.json' is also input 2" merge p2.json p1.json p2.json
run measure a.asc b.asc --tile=16 --shard=2/13 --partial=lod.json --lod=0.2 --quiet
expect_refused "lod.json: a part of another measure than p1.json" merge out.json p1.json lod.json
run measure a.asc b.asc --tile=16 --shard=2/13 --partial=nodod.json --quiet
expect_refused "flag '--dod': nodod.json has no DoD" merge out.json p1.json nodod.json p3.json \
  p4.json p5.json p6.json p7.json p8.json p9.json p10.json p11.json p12.json p13.json --dod=x.tif
expect_refused "flag '--shard': a shard's result is partial: give --partial=P.json" \
  measure a.asc b.asc --tile=16 --shard=1/2
expect_refused "flag '--partial': for a tiled measure" measure a.asc b.asc --partial=p.json
expect_refused "flag '--partial' expects a file name ending in .json" \
  measure a.asc b.asc --tile=16 --shard=1/2 --partial=p.txt

# Killed and resumed: a larger pair (GeoTIFFs, read fast a window at a
# time) measured in about 500 tiles, killed once it reports progress.
python3 "$here/make_tiled_pair.py" 1.7 || exit 2
for name in a b; do
  "$bin" transform $name.asc --transform=id.txt --output=big_$name.tif --quiet >/dev/null
done
run measure big_a.tif big_b.tif --json --tile=16 --dod=full.tif --quiet
cp stdout full.json
[[ $rc -eq 0 ]] || fail "the uninterrupted run: exit $rc"
# SIGNAL [FLAGS]: start the run, send SIGNAL once it reports 60 tiles done
# (rows of 26 tiles: a row's state is written by then).
kill_when_progress() {
  # Emptied here: the background command's own redirection may come after
  # the first look below, which would then read the previous run's progress
  # and kill this one before it starts (seen once in CI).
  : >cut.err
  "$bin" measure big_a.tif big_b.tif --json --tile=16 --dod=cut.tif "${@:2}" >cut.json 2>cut.err &
  local pid=$! i done
  for ((i = 0; i < 600; i++)); do
    done=$(grep -o "tiles, [0-9]*" cut.err | tail -1 | tr -dc 0-9)
    [[ ${done:-0} -ge 60 ]] && break
    sleep 0.1
  done
  kill -"$1" $pid
  { wait $pid; } 2>/dev/null  # no "Killed" line from the shell
}
kill_when_progress KILL
checks=$((checks + 1))
[[ -s cut.tif.resume/state.json && ! -e cut.tif ]] ||
  fail "SIGKILL: expected the state in cut.tif.resume/ and no DoD (was the run too fast to kill?)"
expect_refused "'cut.tif.resume' holds an interrupted tiled measure: add --resume (Python: resume=True) to continue it" \
  measure big_a.tif big_b.tif --tile=16 --dod=cut.tif
expect_refused "flag '--resume': 'cut.tif.resume/state.json' is of another measure" \
  measure big_a.tif big_b.tif --tile=16 --dod=cut.tif --lod=0.3 --resume
kill_when_progress TERM --resume
checks=$((checks + 1))
grep -qE "resuming: [1-9][0-9]* of [0-9]+ tile rows already done" cut.err ||
  fail "the first resume did not start from the finished rows: $(head -2 cut.err)"
run measure big_a.tif big_b.tif --json --tile=16 --dod=cut.tif --resume
[[ $rc -eq 0 ]] || fail "the last resume: exit $rc: $(cat stderr)"
cp stdout cut.json
checks=$((checks + 1))
same_measures full.json cut.json || fail "the resumed run's JSON differs from the uninterrupted one"
checks=$((checks + 1))
same_dod full.tif cut.tif || fail "the resumed run's DoD differs from the uninterrupted one"
checks=$((checks + 1))
[[ ! -e cut.tif.resume ]] || fail "the state directory was left behind after the resumed run"

echo "$checks checks, $failures failed"
[[ $failures -eq 0 ]]

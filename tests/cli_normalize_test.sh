#!/usr/bin/env bash
# End-to-end tests of `surfreg normalize` on the shipped mannequin head
# (configs/data/mannequin_head.off): the written height field is centred
# (Σx = Σy = 0) with max z = 0, the JSON summary agrees with the file, the
# known orientation (-90,0,0) maps the nose tip (the least y) to z = 0, and
# bad input exits 2 with one line on stderr and no output file.
# Usage: cli_normalize_test.sh SURFREG_BINARY
# Needs python3 (standard library). Paths are relative to the project root.
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
head=configs/data/mannequin_head.off
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0

# check_face FILE JSON: the height field in FILE is centred with max z = 0
# and has as many points as the JSON's "kept".
check_face() {
  python3 - "$1" "$2" <<'PY'
import json, sys
pts = [tuple(map(float, l.split()[:3])) for l in open(sys.argv[1]) if l.strip() and l[0] != '#']
summary = json.loads(open(sys.argv[2]).read())
n = len(pts)
scale = max(max(abs(c) for c in p) for p in pts)
sx = sum(p[0] for p in pts); sy = sum(p[1] for p in pts); top = max(p[2] for p in pts)
problems = []
if n != summary["kept"]: problems.append("%d points, JSON kept %d" % (n, summary["kept"]))
if abs(sx) > 1e-9 * n * scale or abs(sy) > 1e-9 * n * scale: problems.append("sums %g %g" % (sx, sy))
if top != 0.0: problems.append("max z %r" % top)
if summary["kept"] + summary["hidden"] + summary["beyond_depth"] != summary["vertices"]:
    problems.append("counts do not add up")
print("; ".join(problems))
sys.exit(1 if problems else 0)
PY
}

# --- the head, automatic orientation ---
run normalize "$head" --output="$tmp/face.xyz" --json
if [[ $rc -ne 0 || -s "$tmp/stderr" ]]; then
  fail "normalize auto"
else
  cp "$tmp/stdout" "$tmp/auto.json"
  check_face "$tmp/face.xyz" "$tmp/auto.json" >"$tmp/stderr" || fail "auto face: $(cat "$tmp/stderr")"
fi

# --- the known orientation, binary PLY output, depth limit ---
run normalize "$head" --orientation=-90,0,0 --depth_limit=8 --output="$tmp/face.ply" --json
if [[ $rc -ne 0 ]]; then
  fail "normalize -90,0,0"
else
  cp "$tmp/stdout" "$tmp/given.json"
  python3 - "$tmp/given.json" <<'PY' >"$tmp/stderr" || fail "given: $(cat "$tmp/stderr")"
import json, sys
s = json.loads(open(sys.argv[1]).read())
bad = []
# The nose tip is the vertex with the least y (-16.736843) and becomes z = 0.
if abs(s["nose_tip_input"][1] + 16.736843) > 1e-9: bad.append("nose tip %r" % s["nose_tip_input"])
if abs(s["translation"][2] + 16.736843) > 1e-9: bad.append("tz %r" % s["translation"][2])
if s["beyond_depth"] <= 0: bad.append("depth_limit dropped nothing")
if abs(s["rotation_vector_deg"][0] + 90) > 1e-9: bad.append("rv %r" % s["rotation_vector_deg"])
print("; ".join(bad)); sys.exit(1 if bad else 0)
PY
  # The PLY reads back through the CLI's own reader as the same count.
  run triangulate "$tmp/face.ply" --json
  [[ $rc -eq 0 ]] || fail "triangulate the written PLY"
fi

# --- text summary ---
run normalize "$head"
[[ $rc -eq 0 ]] && grep -q "rotation vector" "$tmp/stdout" && grep -q "hidden" "$tmp/stdout" ||
  fail "text summary"

# --- errors: exit 2, one line, no output file ---
expect_error() {  # expect_error WHAT ARGS...
  local what=$1
  shift
  run "$@"
  if [[ $rc -ne 2 || $(wc -l <"$tmp/stderr") -ne 1 || -s "$tmp/stdout" ]]; then
    fail "$what: expected exit 2 and one line"
  fi
  if ls "$tmp" | grep -q '^bad'; then
    fail "$what: an output file was written"
  fi
}
expect_error "missing file" normalize "$tmp/missing.off" --output="$tmp/bad.xyz"
expect_error "bad orientation" normalize "$head" --orientation=1,2 --output="$tmp/bad.xyz"
grep -q "flag '--orientation'" "$tmp/stderr" || fail "the message names the flag"
expect_error "negative depth" normalize "$head" --depth_limit=-1 --output="$tmp/bad.xyz"
expect_error "bad output format" normalize "$head" --output="$tmp/bad.png"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' >"$tmp/broken.off"
expect_error "index out of range" normalize "$tmp/broken.off" --output="$tmp/bad.xyz"
grep -q "broken.off:6:" "$tmp/stderr" || fail "the message names file:line"

if [[ $failures -ne 0 ]]; then
  echo "$failures of $checks checks failed"
  exit 1
fi
echo "all $checks normalize CLI checks passed"

#!/usr/bin/env bash
# End-to-end tests of `surfreg measure` on the sample pair in configs/data
# (volcano_a.xyz: the 87 x 61 grid; volcano_b.xyz: 4000 random points on its
# bilinear surface): the JSON contract, exact identities (A against itself, A
# against A shifted up, swapping A and B), the volume and weight modes, and
# the one-line error contract (exit 2).
# Usage: cli_measure_test.sh SURFREG_BINARY
# Needs python3 (standard library). Paths are relative to the project root
# (this script's parent folder), whatever the current directory.
set -u
source "$(dirname -- "$(realpath -- "$0")")/cli_harness.sh"  # fail, run
if [[ $# -ne 1 ]]; then
  echo "usage: $0 SURFREG_BINARY" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$(dirname -- "$(realpath -- "$0")")/.." || exit 2
a=configs/data/volcano_a.xyz
b=configs/data/volcano_b.xyz
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0

# measure_json NAME ARGS...: runs `surfreg measure ARGS... --json`, expects
# exit 0, a clean stderr and one strict JSON object (no NaN or Infinity),
# saved as $tmp/NAME.json. Returns 1 (after reporting) otherwise.
measure_json() {
  local name=$1
  shift
  run measure "$@" --json
  if [[ $rc -ne 0 ]]; then
    fail "measure $* --json: expected exit 0"
    return 1
  elif [[ -s "$tmp/stderr" ]]; then
    fail "measure $* --json: expected a clean stderr"
    return 1
  elif ! python3 -c '
import json, sys
def reject(constant):
    raise ValueError("not JSON: " + constant)
json.loads(sys.stdin.read(), parse_constant=reject)
' <"$tmp/stdout"; then
    fail "measure $* --json: stdout is not exactly one strict JSON object"
    return 1
  fi
  cp "$tmp/stdout" "$tmp/$name.json"
}

# check WHAT PYTHON_CODE: runs the code with r(NAME) = the parsed
# $tmp/NAME.json, hull_area(path), inside_hull(path, x, y) and close(x, y,
# rel) defined; an assertion failure (or any exception) fails the check.
check() {
  local what=$1 code=$2
  checks=$((checks + 1))
  if ! python3 -c '
import json, os, sys
def r(name):
    with open(os.path.join(sys.argv[2], name + ".json")) as f:
        return json.load(f)
def points(path):
    with open(path) as f:
        return [tuple(map(float, l.split()[:2])) for l in f if l.strip() and not l.startswith("#")]
def hull(pts):
    pts = sorted(set(pts))
    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1]) -
                                     (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]
    return half(pts) + half(pts[::-1])  # counter-clockwise
def hull_area(path):
    h = hull(points(path))
    return 0.5 * sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(h, h[1:] + h[:1]))
def inside_hull(path, x, y):
    h = hull(points(path))
    return all((q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]) > 0
               for p, q in zip(h, h[1:] + h[:1]))
def close(x, y, rel):
    return abs(x - y) <= rel * max(abs(x), abs(y))
exec(sys.argv[1])
' "$code" "$tmp"; then
    echo "FAIL: $what"
    failures=$((failures + 1))
  fi
}

# expect_input_error TEXT ARGS...: exit 2, stderr exactly one line, starting
# with "surfreg: error:" and containing TEXT; nothing on stdout.
expect_input_error() {
  local text=$1
  shift
  run "$@"
  local lines
  lines=$(wc -l <"$tmp/stderr")
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $lines -ne 1 ]]; then
    fail "surfreg $*: expected exactly one line on stderr, got $lines"
  elif ! head -1 "$tmp/stderr" | grep -q '^surfreg: error: '; then
    fail "surfreg $*: stderr does not start with 'surfreg: error: '"
  elif ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: stderr does not contain '$text'"
  elif [[ -s "$tmp/stdout" ]]; then
    fail "surfreg $*: expected no stdout"
  fi
}

# expect_usage_error ARGS...: exit 2, one "surfreg: error:" line, then usage.
expect_usage_error() {
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif ! head -1 "$tmp/stderr" | grep -q '^surfreg: error: '; then
    fail "surfreg $*: stderr does not start with 'surfreg: error: '"
  elif [[ $(grep -c '^surfreg: error: ' "$tmp/stderr") -ne 1 ]]; then
    fail "surfreg $*: expected exactly one error line"
  elif ! grep -q 'usage: surfreg measure' "$tmp/stderr"; then
    fail "surfreg $*: no measure usage line on stderr"
  fi
}

# Test inputs derived from the pair (python, so the numbers stay exact).
python3 - "$a" "$b" "$tmp" <<'EOF' || { echo "FAIL: cannot make the test inputs"; exit 1; }
import sys
a, b, tmp = sys.argv[1:]
def rewrite(src, dst, fn):
    with open(src) as f, open(dst, "w") as out:
        for line in f:
            if line.startswith("#") or not line.strip():
                out.write(line)
            else:
                out.write(fn(*map(float, line.split())) + "\n")
# z + 1.5 exactly (the grid's heights are whole metres).
rewrite(a, tmp + "/a_up.xyz", lambda x, y, z: f"{x!r} {y!r} {z + 1.5!r}")
# B moved 10 km east: no overlap with A.
rewrite(b, tmp + "/b_far.xyz", lambda x, y, z: f"{x + 10000:.3f} {y:.3f} {z:.3f}")
with open(tmp + "/west.txt", "w") as f:  # the west half of the grid, as a closed ring
    f.write("# west half of volcano_a: x in [0, 430], y in [0, 600]\n"
            "0 0\n430 0\n430 600  # north-east corner\n\n0 600\n0 0\n")
with open(tmp + "/inner.txt", "w") as f:  # well inside B's hull
    f.write("20 20\n430 20\n430 580\n20 580\n")
with open(tmp + "/bad_line.txt", "w") as f:
    f.write("# a polygon\n0 0\n430 0\n430 6O0\n0 600\n")
with open(tmp + "/three_numbers.txt", "w") as f:
    f.write("0 0\n430 0 1\n0 600\n")
with open(tmp + "/two_vertices.txt", "w") as f:
    f.write("0 0\n430 0\n")
EOF

keys='["rho_d", "rho_d_axial", "rho_s", "overlap_area", "mean_abs_dz", "signed_volume",
       "volume_above", "volume_below", "n_points_a", "n_points_b", "n_overlap_nodes", "timings",
       "file_a", "file_b", "volume_mode", "weight_mode", "n_duplicates_a", "n_duplicates_b",
       "n_cells", "weight_integral", "domain", "domain_area_a", "domain_area_b",
       "excluded_area_a", "excluded_area_b"]'
stages='["read", "triangulate", "domain", "spanning_tree", "locate", "interpolate", "volume",
         "total"]'

# --- the volcano pair ----------------------------------------------------------

if measure_json ab "$a" "$b"; then
  check "measure A B: keys, counts, overlap = B's data domain, small gap" "
ab = r('ab')
missing = [k for k in $keys if k not in ab] + ['timings.' + k for k in $stages if k not in ab['timings']]
assert not missing, missing
assert all(ab['timings'][k] >= 0 for k in $stages), ab['timings']
assert ab['file_a'] == '$a' and ab['file_b'] == '$b', (ab['file_a'], ab['file_b'])
assert ab['volume_mode'] == 'overlay' and ab['weight_mode'] == 'uniform', ab
assert ab['n_points_a'] == 5307 and ab['n_points_b'] == 4000, ab
assert ab['n_duplicates_a'] == 0 and ab['n_duplicates_b'] == 0, ab
assert ab['n_overlap_nodes'] > 4000 and ab['n_cells'] > 0, ab
hull_b = hull_area('$b')
print('  overlap_area %.6f m², hull of B %.6f m² (ratio %.9f)' % (ab['overlap_area'], hull_b, ab['overlap_area'] / hull_b))
# A (the whole grid) is data everywhere; B (4000 random points) loses its
# hull's outline slivers: Ω is B's data domain.
assert ab['domain'] == 'data', ab
assert close(ab['domain_area_a'], 860 * 600, 1e-12) and abs(ab['excluded_area_a']) < 1e-6, ab
assert close(ab['excluded_area_b'], hull_b - ab['domain_area_b'], 1e-9), (ab, hull_b)
assert 0.97 * hull_b < ab['domain_area_b'] < hull_b, (ab['domain_area_b'], hull_b)
assert close(ab['overlap_area'], ab['domain_area_b'], 1e-9), ab
print('  rho_d %.6f m³, rho_d_axial %.6f m, mean_abs_dz %.6f m, rho_s %.6g' % (ab['rho_d'], ab['rho_d_axial'], ab['mean_abs_dz'], ab['rho_s']))
print('  signed %.6f m³ = above %.6f - below %.6f' % (ab['signed_volume'], ab['volume_above'], ab['volume_below']))
assert ab['rho_d'] >= 0 and ab['rho_d_axial'] >= 0, ab
assert ab['overlap_area'] <= 860 * 600 * (1 + 1e-12), ab
assert close(ab['weight_integral'], ab['overlap_area'], 1e-12), ab
assert 0 < ab['mean_abs_dz'] < 2 and 0 < ab['rho_d_axial'] < 2, ab
assert close(ab['rho_d'], ab['mean_abs_dz'] * ab['overlap_area'], 1e-9), ab
assert close(ab['rho_s'], 1 / ab['rho_d'], 1e-12), ab
assert close(ab['rho_d'], ab['volume_above'] + ab['volume_below'], 1e-9), ab
assert abs(ab['signed_volume'] - (ab['volume_above'] - ab['volume_below'])) <= 1e-9 * ab['rho_d'], ab
"
fi

run measure "$a" "$b"
if [[ $rc -ne 0 ]]; then
  fail "measure A B (text): expected exit 0"
elif [[ -s "$tmp/stderr" ]]; then
  fail "measure A B (text): expected a clean stderr"
elif ! grep -Eq '^rho_d .*[0-9] units³' "$tmp/stdout" || ! grep -q '^overlap area:' "$tmp/stdout" ||
     ! grep -q '^volume above:' "$tmp/stdout" || ! grep -q '^time total:' "$tmp/stdout"; then
  fail "measure A B (text): expected rho_d with units³, the overlap area, volumes and timings"
fi

# --- exact identities --------------------------------------------------------

if measure_json aa "$a" "$a"; then
  check "measure A A: zero gap" "
aa = r('aa')
assert aa['rho_d'] == 0 and aa['rho_d_axial'] == 0 and aa['rho_s'] == 1, aa
assert aa['signed_volume'] == 0 and aa['volume_above'] == 0 and aa['volume_below'] == 0, aa
assert aa['mean_abs_dz'] == 0 and close(aa['overlap_area'], 860 * 600, 1e-12), aa
"
fi

if measure_json ba "$b" "$a"; then
  check "measure B A = measure A B with above and below swapped" "
ab, ba = r('ab'), r('ba')
assert close(ab['rho_d'], ba['rho_d'], 1e-9), (ab['rho_d'], ba['rho_d'])
assert close(ab['volume_above'], ba['volume_below'], 1e-9), (ab['volume_above'], ba['volume_below'])
assert close(ab['volume_below'], ba['volume_above'], 1e-9), (ab['volume_below'], ba['volume_above'])
assert close(ab['overlap_area'], ba['overlap_area'], 1e-9), (ab['overlap_area'], ba['overlap_area'])
assert ab['n_overlap_nodes'] == ba['n_overlap_nodes'], (ab['n_overlap_nodes'], ba['n_overlap_nodes'])
"
fi

if measure_json up "$a" "$tmp/a_up.xyz"; then
  check "measure A (A + 1.5 m): the gap is 1.5 m everywhere" "
up = r('up')
area = up['overlap_area']
assert close(area, 860 * 600, 1e-12), up
assert close(up['rho_d'], 1.5 * area, 1e-9), up
assert close(up['signed_volume'], 1.5 * area, 1e-9), up
assert close(up['volume_above'], 1.5 * area, 1e-9), up
assert up['volume_below'] == 0, up
assert close(up['mean_abs_dz'], 1.5, 1e-9) and close(up['rho_d_axial'], 1.5, 1e-9), up
"
fi

# --- volume and weight modes -------------------------------------------------

if measure_json hull "$a" "$b" --domain=hull; then
  check "--domain=hull: overlap = B's hull" "
ab, h = r('ab'), r('hull')
hull_b = hull_area('$b')
assert h['domain'] == 'hull', h
assert close(h['overlap_area'], hull_b, 1e-9), (h['overlap_area'], hull_b)
assert close(h['domain_area_b'], hull_b, 1e-9) and h['excluded_area_b'] == 0, h
assert h['overlap_area'] > ab['overlap_area'] and h['n_overlap_nodes'] >= ab['n_overlap_nodes'], h
"
fi

# Over the data domain the union's triangles are kept where their centroid
# is in Ω: an area close to the overlay's, not the same.
if measure_json union "$a" "$b" --volume=union; then
  check "--volume=union: close to overlay on the pair" "
ab, un = r('ab'), r('union')
print('  union rho_d %.6f m³ vs overlay %.6f m³' % (un['rho_d'], ab['rho_d']))
assert un['volume_mode'] == 'union', un
assert close(un['rho_d'], ab['rho_d'], 0.10), (un['rho_d'], ab['rho_d'])
assert close(un['overlap_area'], ab['overlap_area'], 1e-3), (un['overlap_area'], ab['overlap_area'])
"
fi

if measure_json union_hull "$a" "$b" --volume=union --domain=hull; then
  check "--volume=union --domain=hull: the union's hull is B's" "
h, un = r('hull'), r('union_hull')
assert close(un['overlap_area'], h['overlap_area'], 1e-9), (un['overlap_area'], h['overlap_area'])
"
fi

if measure_json west "$a" "$a" --weights=mask:"$tmp/west.txt"; then
  check "--weights=mask: A A, west half (edges on the hull)" "
w = r('west')
assert w['weight_mode'] == 'mask' and close(w['overlap_area'], 860 * 600, 1e-12), w
assert close(w['weight_integral'], 430 * 600, 1e-6), w['weight_integral']
assert w['rho_d'] == 0, w
"
fi

# Over the hulls: the rectangle is inside B's hull, while B's data domain may
# leave out a triangle or two inside it (an empty spot of the random samples).
if measure_json inner "$a" "$b" --weights=mask:"$tmp/inner.txt" --domain=hull; then
  check "--weights=mask: A B, a rectangle inside B's hull" "
assert all(inside_hull('$b', x, y) for x, y in ((20, 20), (430, 20), (430, 580), (20, 580)))
w, ab = r('inner'), r('hull')
print('  mask weight_integral %.9f m² (rectangle %d m²), rho_d %.6f m³' % (w['weight_integral'], 410 * 560, w['rho_d']))
assert close(w['weight_integral'], 410 * 560, 1e-6), w['weight_integral']
assert close(w['overlap_area'], ab['overlap_area'], 1e-12), w
assert 0 < w['rho_d'] < ab['rho_d'], (w['rho_d'], ab['rho_d'])
assert close(w['mean_abs_dz'], w['rho_d'] / w['weight_integral'], 1e-9), w
"
fi

# --- bad input: exit 2, one line naming what is wrong ------------------------

expect_input_error "configs/data/no_such_b.xyz: cannot open" measure "$a" configs/data/no_such_b.xyz
expect_input_error "configs/data/no_such_a.xyz: cannot open" measure configs/data/no_such_a.xyz "$b"
expect_input_error "'--volume'" measure "$a" "$b" --volume=foo
expect_input_error "'--weights'" measure "$a" "$b" --weights=bogus
expect_input_error "flag '--domain' expects one of data, hull, got 'convex'" \
  measure "$a" "$b" --domain=convex
expect_input_error "flag '--domain_max_edge_spacings' expects a number in [1, 100], got '0.5'" \
  measure "$a" "$b" --domain_max_edge_spacings=0.5
expect_input_error "'--weights'" measure "$a" "$b" --weights=mask:
expect_input_error "$tmp/bad_line.txt:4: y is not a number: '6O0'" \
  measure "$a" "$b" --weights=mask:"$tmp/bad_line.txt"
expect_input_error "$tmp/three_numbers.txt:2:" \
  measure "$a" "$b" --weights=mask:"$tmp/three_numbers.txt"
expect_input_error "$tmp/two_vertices.txt: " \
  measure "$a" "$b" --weights=mask:"$tmp/two_vertices.txt"
expect_input_error "$tmp/no_such_mask.txt: cannot open" \
  measure "$a" "$b" --weights=mask:"$tmp/no_such_mask.txt"
expect_input_error "" measure "$a" "$tmp/b_far.xyz"
expect_input_error "" measure "$a" "$tmp/b_far.xyz" --json

# --- bad usage -----------------------------------------------------------------

expect_usage_error measure "$a"
expect_usage_error measure
expect_usage_error measure "$a" "$b" "$b"
run help measure
if [[ $rc -ne 0 ]] || ! grep -q 'usage: surfreg measure A B' "$tmp/stdout"; then
  fail "help measure: expected the measure usage line"
fi

echo "$((checks - failures)) of $checks checks passed"
[[ $failures -eq 0 ]]

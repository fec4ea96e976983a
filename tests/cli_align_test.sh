#!/usr/bin/env bash
# End-to-end tests of `surfreg align`: the one-line error contract for bad
# configs, flags and files (exit 2, nothing written), and the two example
# configs (configs/*.yaml): summary, transform JSON, aligned surface, CSV
# log, and a loose check that the known motion of the example data is
# recovered (the tight accuracy tests are registration's own).
# Usage: cli_align_test.sh SURFREG_BINARY
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
ref=configs/data/volcano_a.xyz
mov=configs/data/volcano_moved.xyz
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$tmp/out  # every output of the error cases goes here: it must stay empty
mkdir "$out"
failures=0
checks=0

# Runs surfreg with the given arguments; sets rc, leaves $tmp/stdout and $tmp/stderr.
# config NAME TEXT: writes $tmp/NAME.yaml (outputs pointing into $out).
config() {
  printf '%s\n' "$2" >"$tmp/$1.yaml"
}

# expect_error TEXT ARGS...: exit 2, exactly one stderr line "surfreg: error:
# ..." containing TEXT, no stdout, and nothing written to $out.
expect_error() {
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
  elif [[ -n "$(ls -A "$out")" ]]; then
    fail "surfreg $*: files were written: $(ls -A "$out")"
    rm -f "$out"/*
  fi
}

# expect_usage_error TEXT ARGS...: exit 2, one "surfreg: error:" line with
# TEXT, then the align usage line.
expect_usage_error() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $(grep -c '^surfreg: error: ' "$tmp/stderr") -ne 1 ]] || ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: expected one error line containing '$text'"
  elif ! grep -q 'usage: surfreg align' "$tmp/stderr"; then
    fail "surfreg $*: no align usage line on stderr"
  fi
}

# check WHAT PYTHON_CODE: runs the code with load(path) (strict JSON),
# expected(path) (the reference_from_moving matrix in a data file's header)
# and motion_error(result, expected, points) defined; any exception fails.
check() {
  local what=$1 code=$2
  checks=$((checks + 1))
  if ! python3 -c '
import json, math, sys
def reject(constant):
    raise ValueError("not JSON: " + constant)
def load(path):
    with open(path) as f:
        return json.loads(f.read(), parse_constant=reject)
def expected(path):
    with open(path) as f:
        for line in f:
            if line.startswith("# reference_from_moving:"):
                return json.loads(line.split(":", 1)[1])
    raise ValueError("no reference_from_moving line in " + path)
def apply(m, p):
    return [sum(m[i][k] * p[k] for k in range(3)) + m[i][3] for i in range(3)]
def motion_error(m, e, points):
    """(angle between the rotations in degrees, largest distance between the
    two motions images of points)."""
    trace = sum(m[i][k] * e[i][k] for i in range(3) for k in range(3))
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (trace - 1) / 2))))
    return angle, max(math.dist(apply(m, p), apply(e, p)) for p in points)
exec(sys.argv[1])
' "$code"; then
    echo "FAIL: $what"
    failures=$((failures + 1))
  fi
}

# --- bad configs, flags and files: exit 2, one line, nothing written ----------

config unknown "reference: $ref
moving: $mov
cots: volume
output: $out/t.json"
expect_error "$tmp/unknown.yaml:3: unknown key 'cots' (did you mean 'cost'?)" \
  align --config "$tmp/unknown.yaml"

config type "reference: $ref
moving: $mov
output: $out/t.json
max_iterations: many"
expect_error "$tmp/type.yaml:4: key 'max_iterations' expects an integer >= 1, got 'many'" \
  align --config "$tmp/type.yaml"

config enum "reference: $ref
moving: $mov
loss: l1
output: $out/t.json"
expect_error "$tmp/enum.yaml:3: key 'loss' expects one of none, huber, soft_l1, cauchy, got 'l1'" \
  align --config "$tmp/enum.yaml"

config list "- reference: $ref
- moving: $mov"
expect_error "$tmp/list.yaml: expected a YAML mapping" align --config "$tmp/list.yaml"
config syntax "reference: $ref
  moving: $mov"
expect_error "$tmp/syntax.yaml:2: not valid YAML" align --config "$tmp/syntax.yaml"
config twice "reference: $ref
moving: $mov
reference: $mov"
expect_error "$tmp/twice.yaml:3: key 'reference' given twice (also at line 1)" \
  align --config "$tmp/twice.yaml"

config missing "reference: configs/data/no_such.xyz
moving: $mov
output: $out/t.json"
expect_error "$tmp/missing.yaml:1: key 'reference': configs/data/no_such.xyz: cannot open" \
  align --config "$tmp/missing.yaml"
config good "reference: $ref
moving: $mov
output: $out/t.json
aligned: $out/t.ply
log: $out/t.csv"
expect_error "flag '--moving': configs/data/no_such.xyz: cannot open" \
  align --config "$tmp/good.yaml" --moving=configs/data/no_such.xyz
expect_error "flag '--max_iterations' expects an integer >= 1, got '1e9x'" \
  align --config "$tmp/good.yaml" --max_iterations=1e9x
expect_error "argument MOVING: configs/data/no_such.xyz: cannot open" \
  align "$ref" configs/data/no_such.xyz --output="$out/t.json"
config no_moving "reference: $ref"
expect_error "$tmp/no_moving.yaml: no 'moving' surface given" align --config "$tmp/no_moving.yaml"

config outdir "reference: $ref
moving: $mov
output: $out/no_such_dir/t.json"
expect_error "$tmp/outdir.yaml:3: key 'output': cannot write '$out/no_such_dir/t.json': directory '$out/no_such_dir' does not exist" \
  align --config "$tmp/outdir.yaml"
expect_error "flag '--log': cannot write '$out/nope/i.csv'" \
  align "$ref" "$mov" --log="$out/nope/i.csv" --output="$out/t.json"
expect_error "flag '--aligned': cannot write a surface as '$out/m.obj'" \
  align "$ref" "$mov" --aligned="$out/m.obj"
expect_error "flag '--aligned': '$mov' is also the moving file" align "$ref" "$mov" --aligned="$mov"
expect_error "flag '--config': $tmp/none.yaml: cannot open" align --config "$tmp/none.yaml"
expect_error "flag '--levels' expects an integer in [1, 8], got '0'" \
  align "$ref" "$mov" --levels=0 --output="$out/t.json"
expect_error "flag '--free' expects a list of rx, ry, rz, tx, ty, tz" \
  align "$ref" "$mov" --free=rx,yaw
expect_error "flag '--mask': $tmp/no_mask.txt: cannot open" \
  align "$ref" "$mov" --mask="$tmp/no_mask.txt" --output="$out/t.json"
printf '0 0\n400 0\n400 400\n' >"$tmp/mask.txt"
expect_error "flag '--trim_fraction': " align "$ref" "$mov" --cost=volume --trim_fraction=0.1 \
  --mask="$tmp/mask.txt" --output="$out/t.json"

# Align's own InputErrors (no overlap at the initial motion) keep the contract.
python3 - "$mov" "$tmp/far.xyz" <<'EOF'
import sys
with open(sys.argv[1]) as f, open(sys.argv[2], "w") as out:
    for line in f:
        if not line.startswith("#") and line.strip():
            x, y, z = map(float, line.split())
            out.write(f"{x + 10000:.3f} {y:.3f} {z:.3f}\n")
EOF
expect_error "" align "$ref" "$tmp/far.xyz" --output="$out/t.json" --aligned="$out/t.ply"

expect_usage_error "not both" align --config "$tmp/unknown.yaml" "$ref" "$mov"
expect_usage_error "missing REFERENCE MOVING or --config" align
expect_usage_error "for a config file: --config configs/terrain_volcano.yaml" \
  align configs/terrain_volcano.yaml
expect_usage_error "too many arguments" align "$ref" "$mov" "$mov"
run help align
if [[ $rc -ne 0 ]] || ! grep -q 'usage: surfreg align' "$tmp/stdout"; then
  fail "help align: expected the align usage line"
fi

# --- the example configs -------------------------------------------------------

# example NAME CONFIG MOVING_FILE: runs the config with its outputs moved to
# $tmp, then checks the summary, the JSON, the aligned surface and the log.
example() {
  local name=$1 config=$2 moving=$3
  echo old >"$tmp/$name.json"  # replaced whole by the run
  run align --config "$config" --output="$tmp/$name.json" --aligned="$tmp/$name.ply" \
    --log="$tmp/$name.csv"
  if [[ $rc -ne 0 ]]; then
    fail "align --config $config: expected exit 0"
    return
  fi
  for label in verdict: rotation: translation: stddev: "rho'_d:" "mean |dz|:" overlap: time:; do
    grep -q "^$label" "$tmp/stdout" || fail "align --config $config: no '$label' line in the summary"
  done
  ls "$tmp" | grep -q '\.tmp-' && fail "align --config $config: a temporary file was left"
  check "$config: JSON keys, known motion recovered, log" "
r = load('$tmp/$name.json')
keys = ['matrix', 'rotation_vector', 'quaternion', 'euler_deg', 'translation', 'stddev', 'before',
        'after', 'iterations', 'termination', 'seconds', 'verdict', 'verdict_reason', 'centre',
        'observability', 'constrained', 'condition_number', 'folded_triangles', 'cost',
        'solve_cost', 'density_ratio', 'chord_correction', 'reference', 'moving']
missing = [k for k in keys if k not in r]
missing += [s + '.' + k for s in ('before', 'after') for k in ('rho_d', 'rho_d_axial',
            'mean_abs_dz', 'overlap_area', 'overlap_fraction', 'n_overlap_nodes') if k not in r[s]]
missing += ['stddev.' + k for k in ('rx', 'ry', 'rz', 'tx', 'ty', 'tz') if k not in r['stddev']]
assert not missing, missing
assert r['verdict'] == 'converged_improved', (r['verdict'], r['verdict_reason'])
assert r['after']['mean_abs_dz'] < r['before']['mean_abs_dz'], (r['before'], r['after'])
assert r['moving'] == '$moving', r['moving']
assert r['solve_cost'] == 'volume', r['solve_cost']  # equal densities (faces would keep it anyway)
assert r['stddev_source'].startswith('sandwich over '), r['stddev_source']  # the volume cost's default
points = [tuple(map(float, l.split()[:3])) for l in open('$moving') if l.strip() and not l.startswith('#')]
xs, ys = [p[0] for p in points], [p[1] for p in points]
spacing = math.sqrt((max(xs) - min(xs)) * (max(ys) - min(ys)) / len(points))
corners = [(x, y, sum(p[2] for p in points) / len(points)) for x in (min(xs), max(xs)) for y in (min(ys), max(ys))]
angle, shift = motion_error(r['matrix'], expected('$moving'), corners + [tuple(r['centre'])])
print('  $name: %s, rotation off by %.5f deg, points off by %.3g (spacing %.3g), %d iterations, %.2f s'
      % (r['verdict'], angle, shift, spacing, r['iterations'], r['seconds']))
assert angle < 0.05 and shift < 0.1 * spacing, (angle, shift, spacing)
rows = open('$tmp/$name.csv').read().splitlines()
assert rows[0] == 'level,start,cost_kind,iteration,cost,step_norm,gradient_norm,seconds', rows[0]
assert len(rows) > 2 and all(len(row.split(',')) == 8 for row in rows), rows[:3]
"
  # The aligned surface reads back, and measures as the JSON's 'after'.
  run measure "$(python3 -c "import json; print(json.load(open('$tmp/$name.json'))['reference'])")" \
    "$tmp/$name.ply" --json
  if [[ $rc -ne 0 ]]; then
    fail "measure of the aligned surface $tmp/$name.ply: expected exit 0"
  else
    cp "$tmp/stdout" "$tmp/$name.measure.json"
    check "$config: the aligned surface measures as 'after'" "
r, m = load('$tmp/$name.json'), load('$tmp/$name.measure.json')
a = r['after']
assert m['n_points_b'] == len([l for l in open('$moving') if l.strip() and not l.startswith('#')])
assert abs(m['rho_d'] - a['rho_d']) <= 1e-6 * a['rho_d'], (m['rho_d'], a['rho_d'])
assert abs(m['overlap_area'] - a['overlap_area']) <= 1e-6 * a['overlap_area'], (m, a)
"
  fi
}

example volcano configs/terrain_volcano.yaml configs/data/volcano_moved.xyz
example face configs/face_mannequin.yaml configs/data/face_b_moved.xyz

# --json: the same JSON on stdout (and in --output); flags override the config.
stamp() { stat -c %Y:%s "$@" 2>/dev/null; }
stamps=$(stamp out/volcano_aligned.ply out/volcano_iterations.csv)
run align --config configs/terrain_volcano.yaml --output="$tmp/j.json" --aligned= --log= \
  --cost=axial --json
if [[ $rc -ne 0 ]]; then
  fail "align --config ... --cost=axial --json: expected exit 0"
elif ! cmp -s "$tmp/stdout" "$tmp/j.json"; then
  fail "align --json: stdout differs from the --output file"
else
  cp "$tmp/stdout" "$tmp/stdout.json"
  check "--json: strict JSON, the flag's cost" "
r = load('$tmp/stdout.json')
assert r['cost'] == 'axial' and r['free'] == ['rx', 'ry', 'rz', 'tx', 'ty', 'tz'], r['cost']
assert r['stddev_source'].startswith('sandwich over '), r['stddev_source']  # the axial cost's too
"
fi
[[ "$(stamp out/volcano_aligned.ply out/volcano_iterations.csv)" == "$stamps" ]] ||
  fail "--aligned= and --log= (no file) still wrote the config's outputs"

# The positional form, a partial parameter set, with the .xyz writer.
run align "$ref" "$mov" --free=translation --aligned="$tmp/t.xyz" --json
if [[ $rc -ne 0 ]]; then
  fail "align REF MOV --free=translation: expected exit 0"
else
  cp "$tmp/stdout" "$tmp/t.json"
  check "--free=translation: rotation stays zero; the .xyz output reads back" "
r = load('$tmp/t.json')
assert r['free'] == ['tx', 'ty', 'tz'] and r['rotation_vector'] == [0, 0, 0], r['rotation_vector']
assert r['stddev']['rx'] == 0, r['stddev']
n = sum(1 for l in open('$tmp/t.xyz') if l.strip() and not l.startswith('#'))
assert n == 4000, n
"
fi

# Terrain of two resolutions: a quarter of the moving cloud (1000 points
# against the 5307-node grid) is solved with the axial cost at its nodes.
awk '/^#/ || NR % 4 == 0' "$mov" >"$tmp/quarter.xyz"
run align "$ref" "$tmp/quarter.xyz" --output="$tmp/quarter.json"
if [[ $rc -ne 0 ]]; then
  fail "align REF QUARTER: expected exit 0"
else
  grep -q "^solved with:  the axial cost at the sparser surface's nodes" "$tmp/stdout" ||
    fail "align REF QUARTER: no 'solved with:' line in the summary"
  check "two resolutions: the sparser nodes' cost, known motion recovered" "
r = load('$tmp/quarter.json')
assert r['cost'] == 'auto' and r['solve_cost'] == \"axial at the sparser surface's nodes\", r['solve_cost']
assert r['density_ratio'] > 4, r['density_ratio']
assert r['verdict'] == 'converged_improved', (r['verdict'], r['verdict_reason'])
angle, shift = motion_error(r['matrix'], expected('$tmp/quarter.xyz'), [(0, 0, 100), (860, 600, 100)])
print('  quarter: rotation off by %.5f deg, points off by %.3g' % (angle, shift))
assert angle < 0.05 and shift < 1.0, (angle, shift)
"
  run align "$ref" "$tmp/quarter.xyz" --cost=volume --json
  cp "$tmp/stdout" "$tmp/quarter_volume.json"
  check "an explicit --cost=volume is solved with the volume cost" "
r = load('$tmp/quarter_volume.json')
assert r['cost'] == 'volume' and r['solve_cost'] == 'volume', r['solve_cost']
"
  run align "$ref" "$tmp/quarter.xyz" --cost=axial_sparser --json
  cp "$tmp/stdout" "$tmp/quarter_sparser.json"
  check "an explicit --cost=axial_sparser gives the automatic choice's motion" "
r = load('$tmp/quarter_sparser.json'); q = load('$tmp/quarter.json')
assert r['cost'] == 'axial_sparser' and r['solve_cost'] == \"axial at the sparser surface's nodes\", r['solve_cost']
assert max(abs(x - y) for a, b in zip(r['matrix'], q['matrix']) for x, y in zip(a, b)) < 1e-12
"
  run align "$ref" "$tmp/quarter.xyz" --sparser_nodes_ratio=0
  checks=$((checks + 1))
  if [[ $rc -ne 2 ]] || ! grep -qF "unknown flag '--sparser_nodes_ratio=0' (replaced by cost: auto, which" "$tmp/stderr"; then
    fail "a retired key does not say what replaced it: $(cat "$tmp/stderr")"
  fi
fi

# --- an exclude mask with a hole: GeoJSON (OGR) and text give one alignment ---
printf '100 100\n500 100\n500 500\n100 500\n>\n200 200\n300 200\n300 300\n200 300\n' >"$tmp/slide.txt"
if has_part gdal; then  # OGR: not in a build without GDAL
cat >"$tmp/slide.geojson" <<'JSON'
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 1, "properties": {}, "geometry": {"type": "Polygon", "coordinates": [
   [[100, 100], [500, 100], [500, 500], [100, 500], [100, 100]],
   [[200, 200], [200, 300], [300, 300], [300, 200], [200, 200]]]}}]}
JSON
run align "$ref" "$mov" --cost=axial --mask="$tmp/slide.txt" --mask_mode=exclude --covariance=false --json
cp "$tmp/stdout" "$tmp/slide_txt.json"
run align "$ref" "$mov" --cost=axial --mask="$tmp/slide.geojson" --mask_mode=exclude --covariance=false --json
cp "$tmp/stdout" "$tmp/slide_json.json"
check "exclude mask with a hole: GeoJSON = text, known motion recovered" "
t, g = load('$tmp/slide_txt.json'), load('$tmp/slide_json.json')
assert t['verdict'] == g['verdict'] == 'converged_improved', (t['verdict'], g['verdict'])
for i in range(4):
    for k in range(4):
        assert abs(t['matrix'][i][k] - g['matrix'][i][k]) <= 1e-9 * (1 + abs(t['matrix'][i][k])), (t['matrix'], g['matrix'])
angle, shift = motion_error(g['matrix'], expected('$mov'), [(0, 0, 100), (860, 600, 100)])
assert angle < 0.05 and shift < 1.0, (angle, shift)
"
fi  # has_part gdal
expect_error "flag '--mask_mode': needs a mask ('mask')" \
  align "$ref" "$mov" --mask_mode=exclude --output="$out/t.json"
has_part gdal &&
  expect_error "flag '--mask': $tmp/slide.geojson: no layer 'x' (layers: 'slide')" \
  align "$ref" "$mov" --mask="$tmp/slide.geojson" --mask_layer=x --output="$out/t.json"

# --- stable terrain: the changed example (a landslide), found and left out --
changed=configs/data/volcano_changed.xyz
run align "$ref" "$changed" --stable_map="$out/stable.xyz" --json
cp "$tmp/stdout" "$tmp/stable_auto.json"
run align "$ref" "$changed" --stable=all --json
cp "$tmp/stdout" "$tmp/stable_all.json"
check "stable auto: the landslide left out, the known motion closer than fitting all" "
a, w = load('$tmp/stable_auto.json'), load('$tmp/stable_all.json')
s = a['stable']
assert s['mode'] == 'auto' and s['regions'] == 2 and s['settled'] and s['warning'] == '', s
assert 0.85 < s['stable_share'] < 0.95, s
assert w['stable'] == {'mode': 'all'}, w['stable']
pts = [(0, 0, 100), (860, 600, 100)]
ea = motion_error(a['matrix'], expected('$changed'), pts)
ew = motion_error(w['matrix'], expected('$changed'), pts)
assert ea[0] < 0.002 and ea[0] < 0.5 * ew[0], (ea, ew)
rows = [l.split() for l in open('$out/stable.xyz') if not l.startswith('#')]
flags = [int(r[3]) for r in rows]
assert len(rows) == 5307 and set(flags) <= {0, 1, 2}, (len(rows), set(flags))
# the changed samples are within the two 90 m bells (plus their rims), none far off
for r, f in zip(rows, flags):
    x, y = float(r[0]), float(r[1])
    near = min(math.hypot(x - 560, y - 380), math.hypot(x - 640, y - 430))
    assert f != 0 or near < 125, (x, y)
assert sum(f == 0 for f in flags) == s['changed_samples'], (sum(f == 0 for f in flags), s)
"
rm -f "$out"/*
expect_error "flag '--stable_map': a GeoTIFF is on the reference's grid, but the reference is no raster" \
  align "$ref" "$mov" --stable_map="$out/stable.tif" --output="$out/t.json"
expect_error "flag '--stable_map': a PNG map is on the reference's grid, but the reference is no raster" \
  align "$ref" "$mov" --stable_map="$out/stable.png" --output="$out/t.json"
expect_error "flag '--stable' expects one of auto, all, got 'some'" align "$ref" "$mov" --stable=some

echo "$((checks - failures)) of $checks checks passed"
[[ $failures -eq 0 ]]

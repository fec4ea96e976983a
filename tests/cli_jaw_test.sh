#!/usr/bin/env bash
# End-to-end test of `surfreg jaw`: the shipped example configs/jaw_chewing.yaml
# on configs/data/chewing/ against its truth file (every frame within 0.1° and
# 0.05 mm; σ, the path and the helical axes in the outputs), the same without
# boundary_y (the level found within the margin of -35, the same limits), the
# four outputs, --key=value overrides, and bad configs (exit 2, one line on
# stderr, no output file written; a still sequence among them).
# Usage: cli_jaw_test.sh SURFREG_BINARY (needs python3, standard library).
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

outputs=(--output_csv="$tmp/jaw.csv" --output_json="$tmp/jaw.json" --plot="$tmp/jaw.png"
  --path_plot="$tmp/path.png")
written=(jaw.csv jaw.json jaw.png path.png)
if ! has_part plots; then  # a build without Cairo refuses any plot: none
  outputs[2]=--plot=
  outputs[3]=--path_plot=
  written=(jaw.csv jaw.json)
fi

# The outputs against the truth: CSV (frame,rx_deg,...; σ and the path at the
# end) and JSON (matrices, boundary, path, helical axes) agree; every frame
# within 0.1° and 0.05 mm; the boundary given, or found within the margin of -35.
cat >"$tmp/check.py" <<'EOF'
import csv, json, math, statistics, sys
got = list(csv.DictReader(open(sys.argv[1])))
report = json.load(open(sys.argv[2]))
found = sys.argv[3]
columns = list(got[0].keys())
assert columns[:7] == ["frame", "rx_deg", "ry_deg", "rz_deg", "tx", "ty", "tz"], columns
params = ["rx_deg", "ry_deg", "rz_deg", "tx", "ty", "tz"]
sd = ["rx_sd_deg", "ry_sd_deg", "rz_sd_deg", "tx_sd", "ty_sd", "tz_sd"]
assert columns[-12:] == sd + ["path_x", "path_y", "path_z", "path_x_sd", "path_y_sd", "path_z_sd"], columns
truth = list(csv.DictReader(open("configs/data/chewing/truth.csv")))
matrices = report["matrices"]
truth_m = json.load(open("configs/data/chewing/truth.json"))
assert len(got) == len(truth) == len(matrices) == len(truth_m) == 10
boundary = report["boundary"]
assert boundary["found"] == found and boundary["margin"] == 2, boundary
assert abs(boundary["y"] + 35) <= boundary["margin"], boundary
assert report["path"]["rule"] == "lowest", report["path"]
p0 = report["path"]["point_reference"]
axes = report["helical_axes"]
assert [(h["from"], h["to"]) for h in axes] == [(k, k + 1) for k in range(9)], axes
worst_angle = worst_shift = 0.0
ratios = []
for g, t, m, tm, f in zip(got, truth, matrices, truth_m, report["frames"]):
    assert int(g["frame"]) == int(t["frame"])
    # rotation angle of R_got · R_truthᵀ and the translation difference
    r = [[sum(m[i][k] * tm[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1) / 2))))
    shift = math.dist([m[i][3] for i in range(3)], [tm[i][3] for i in range(3)])
    # the CSV says the same as the JSON
    assert all(abs(float(g[k]) - m[i][3]) < 1e-6 for i, k in enumerate(["tx", "ty", "tz"]))
    assert all(abs(float(g[k]) - float(t[k])) < 0.1 for k in ["rx_deg", "ry_deg", "rz_deg"])
    assert all(abs(float(g[k]) - v) <= 1e-6 * abs(v) for k, v in zip(sd, f["stddev"]))
    # the path point is J · p0
    path = [sum(m[i][k] * p0[k] for k in range(3)) + m[i][3] for i in range(3)]
    assert math.dist(path, f["path_point"]) < 1e-9, (path, f["path_point"])
    assert all(abs(float(g["path_" + c]) - v) < 1e-5 for c, v in zip("xyz", path))
    if int(g["frame"]) > 0:  # σ > 0, and the errors in units of it
        assert all(0 < float(g[k]) < 0.05 for k in sd), [g[k] for k in sd]
        ratios += [abs(float(g[k]) - float(t[k])) / float(g[s]) for k, s in zip(params, sd)]
    worst_angle, worst_shift = max(worst_angle, angle), max(worst_shift, shift)
for h in axes:  # a unit direction; the point on the axis closest to the origin
    n, p = h["direction"], h["point"]
    assert h["kind"] == "screw" and abs(math.hypot(*n) - 1) < 1e-9, h
    assert abs(sum(a * b for a, b in zip(n, p))) < 1e-6 and 0 <= h["angle_deg"] <= 180, h
print(f"max error {worst_angle:.4f} deg {worst_shift:.4f} mm; boundary y {boundary['y']:.3f} ({found}); "
      f"median |error|/sigma {statistics.median(ratios):.2f}; largest helical angle "
      f"{max(h['angle_deg'] for h in axes):.3f} deg")
assert worst_angle <= 0.1 and worst_shift <= 0.05, (worst_angle, worst_shift)
EOF

# --- the example: recovers the truth on every frame ---
run jaw --config configs/jaw_chewing.yaml "${outputs[@]}"
if [[ $rc -ne 0 ]]; then
  fail "jaw example: exit code"
else
  for f in "${written[@]}"; do
    [[ -s "$tmp/$f" ]] || fail "jaw example: $f not written"
  done
  grep -q "^jaw: frame 9:" "$tmp/stderr" || fail "jaw example: no progress line for frame 9"
  grep -q "^failed: *0 frames" "$tmp/stdout" || fail "jaw example: summary"
  if ! python3 "$tmp/check.py" "$tmp/jaw.csv" "$tmp/jaw.json" given >"$tmp/check" 2>&1; then
    rc=1
    fail "jaw example: accuracy ($(tail -1 "$tmp/check"))"
  else
    echo "jaw example: $(cat "$tmp/check")"
  fi
fi

# --- without boundary_y: the level found from the frames, the same accuracy ---
run jaw --config configs/jaw_chewing.yaml --boundary_y= --output_csv="$tmp/auto.csv" \
  --output_json="$tmp/auto.json" --plot= --path_plot=
if [[ $rc -ne 0 ]]; then
  fail "jaw automatic boundary: exit code ($(tail -1 "$tmp/stderr"))"
else
  grep -q "^boundary: *y .*automatic" "$tmp/stdout" || fail "jaw automatic boundary: summary line"
  if ! python3 "$tmp/check.py" "$tmp/auto.csv" "$tmp/auto.json" automatic >"$tmp/check" 2>&1; then
    fail "jaw automatic boundary: ($(tail -1 "$tmp/check"))"
  else
    echo "jaw automatic boundary: $(cat "$tmp/check")"
  fi
fi

# --- overrides: a flag wins over the config ---
run jaw --config configs/jaw_chewing.yaml --output_csv="$tmp/volume.csv" --output_json= --plot= --path_plot= \
  --cost=volume --volume_iterations=3 --progress=false
[[ $rc -eq 0 && -s "$tmp/volume.csv" ]] || fail "jaw --cost=volume override"
[[ -s "$tmp/stderr" ]] && fail "jaw --progress=false still prints progress"
run jaw --config configs/jaw_chewing.yaml --output_csv="$tmp/quiet.csv" --output_json= --plot= --path_plot= --quiet
[[ $rc -eq 0 && -s "$tmp/quiet.csv" ]] || fail "jaw --quiet: expected exit 0 and the CSV"
[[ -s "$tmp/stderr" ]] && fail "jaw --quiet still prints progress"

# --- bad configs: exit 2, one line, no output ---
bad() {  # bad NAME EXPECTED_TEXT YAML_LINES...
  local name=$1 expected=$2
  shift 2
  printf '%s\n' "$@" >"$tmp/$name.yaml"
  rm -rf "$tmp/bad_out" && mkdir "$tmp/bad_out"
  local plot=--plot="$tmp/bad_out/a.png"
  has_part plots || plot=--plot=
  run jaw --config "$tmp/$name.yaml" --output_csv="$tmp/bad_out/a.csv" --output_json="$tmp/bad_out/a.json" \
    "$plot"
  if [[ $rc -ne 2 ]]; then
    fail "bad config $name: exit code"
  elif [[ $(wc -l <"$tmp/stderr") -ne 1 ]]; then
    fail "bad config $name: not one line"
  elif ! grep -q -- "$expected" "$tmp/stderr"; then
    fail "bad config $name: message lacks '$expected'"
  elif [[ -n $(ls -A "$tmp/bad_out") ]]; then
    fail "bad config $name: output written"
  fi
}
frames="frames: configs/data/chewing/frames"
bad unknown_key "did you mean 'boundary_y'" "$frames" "boundry_y: -35"
bad wrong_type "key 'max_iterations'" "$frames" "boundary_y: -35" "max_iterations: many"
bad missing_frame "no_such_frame.xyz" "frames: [configs/data/chewing/frames/frame_000.xyz, no_such_frame.xyz]" \
  "boundary_y: -35"
mkdir -p "$tmp/empty"
bad empty_folder "has no surface files" "frames: $tmp/empty" "boundary_y: -35"
frame0=configs/data/chewing/frames/frame_000.xyz
bad still_sequence "cannot be found.*give boundary_y" "frames: [$frame0, $frame0, $frame0]"
bad path_point "key 'path_point'" "$frames" "boundary_y: -35" "path_point: [1, 2]"
bad boundary_too_high "upper part" "$frames" "boundary_y: 500"
run jaw configs/jaw_chewing.yaml
[[ $rc -eq 2 ]] || fail "jaw without --config: exit code"

echo "$checks checks, $failures failures"
[[ $failures -eq 0 ]]

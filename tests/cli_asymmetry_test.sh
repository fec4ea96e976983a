#!/usr/bin/env bash
# End-to-end tests of `surfreg asymmetry`: on the shipped face cloud the JSON
# has the keys of docs/faces.md (initial, refined: rho_d, mean_abs_dz, overlap_area,
# plane.normal, plane.offset), the refined estimate is no worse than the
# initial one, --output holds the same JSON as stdout, and the map is a PNG;
# an exactly symmetric face gives zero asymmetry and the plane x = 0; the
# head mesh (auto orientation) runs; bad input exits 2 with one line and
# writes nothing.
# Usage: cli_asymmetry_test.sh SURFREG_BINARY   (needs python3, standard library)
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
out=$tmp/out  # stays empty: only the failing runs point here
mkdir "$out"
failures=0
checks=0

# expect_error TEXT LINES ARGS...: exit 2, LINES lines on stderr mentioning TEXT, no output file.
expect_error() {
  local text=$1 lines=$2
  shift 2
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $(wc -l <"$tmp/stderr") -ne $lines ]]; then
    fail "surfreg $*: expected $lines line(s) on stderr"
  elif ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: stderr does not mention '$text'"
  elif [[ -n $(ls -A "$out") ]]; then
    fail "surfreg $*: wrote $(ls -A "$out")"
  fi
}

# --- the shipped face cloud: keys, no worse, --output = stdout, the map ---
good=$tmp/good
mkdir "$good"
# (No map from a build without Cairo, which refuses one.)
map=(--map="$good/map.png")
has_part plots || map=()
run asymmetry configs/data/face_a.xyz --json "${map[@]}" --output="$good/asym.json"
if [[ $rc -ne 0 ]]; then
  fail "asymmetry face_a.xyz --json"
else
  python3 - "$tmp/stdout" "$good/asym.json" "$good/map.png" "${#map[@]}" <<'PY' || fail "asymmetry face_a.xyz: JSON"
import json, math, os, sys
stdout = json.load(open(sys.argv[1]))
written = json.load(open(sys.argv[2]))
errors = []
if stdout != written:
    errors.append("--output differs from stdout")
for name in ("initial", "refined"):
    e = stdout[name]
    for key in ("rho_d", "mean_abs_dz", "overlap_area", "plane"):
        if key not in e:
            errors.append("%s: no %s" % (name, key))
    n, d = e["plane"]["normal"], e["plane"]["offset"]
    if len(n) != 3 or abs(math.sqrt(sum(v * v for v in n)) - 1) > 1e-12 or n[0] <= 0:
        errors.append("%s: normal %s not unit with n_x > 0" % (name, n))
    if not math.isfinite(d):
        errors.append("%s: offset %s" % (name, d))
    # rho_d per unit area is the mean |dz| over the overlap.
    if abs(e["rho_d"] / e["overlap_area"] - e["mean_abs_dz"]) > 1e-9 * e["mean_abs_dz"]:
        errors.append("%s: rho_d / overlap_area != mean_abs_dz" % name)
i, r = stdout["initial"], stdout["refined"]
if i["plane"]["normal"] != [1, 0, 0] or i["plane"]["offset"] != 0:
    errors.append("initial plane is not x = 0: %s" % i["plane"])
if r["mean_abs_dz"] > i["mean_abs_dz"]:
    errors.append("refined worse than initial")
cos = sum(a * b for a, b in zip(i["plane"]["normal"], r["plane"]["normal"]))
angle = math.degrees(math.acos(min(1.0, abs(cos))))
if abs(angle - stdout["angle_deg"]) > 1e-6:
    errors.append("angle_deg %s, normals give %s" % (stdout["angle_deg"], angle))
if os.path.exists(sys.argv[3]) != bool(int(sys.argv[4])):
    errors.append("map written: %s, expected %s" % (os.path.exists(sys.argv[3]), sys.argv[4]))
elif os.path.exists(sys.argv[3]) and open(sys.argv[3], "rb").read(8) != b"\x89PNG\r\n\x1a\n":
    errors.append("map is not a PNG")
if errors:
    print("\n".join(errors))
    sys.exit(1)
PY
fi

# --- an exactly symmetric face: zero asymmetry, the plane x = 0 ---
python3 - configs/data/face_a.xyz "$tmp/symmetric.xyz" <<'PY'
import sys
points = [tuple(map(float, l.split()[:3])) for l in open(sys.argv[1]) if l.strip() and l[0] != "#"]
mean = sum(p[0] for p in points) / len(points)
with open(sys.argv[2], "w") as f:
    for x, y, z in points:
        if x - mean > 1e-6:
            f.write("%r %r %r\n%r %r %r\n" % (x - mean, y, z, mean - x, y, z))
PY
run asymmetry "$tmp/symmetric.xyz" --json --quiet
if [[ $rc -ne 0 ]]; then
  fail "asymmetry symmetric.xyz"
else
  python3 - "$tmp/stdout" <<'PY' || fail "asymmetry symmetric.xyz: not zero"
import json, sys
j = json.load(open(sys.argv[1]))
for name in ("initial", "refined"):
    e = j[name]
    assert e["rho_d"] < 1e-9, (name, e["rho_d"])
    assert abs(e["plane"]["normal"][0] - 1) < 1e-12 and abs(e["plane"]["offset"]) < 1e-9, e["plane"]
PY
fi

# --- the head mesh, auto orientation, text output ---
if [[ -f configs/data/mannequin_head.off ]]; then
  run asymmetry configs/data/mannequin_head.off --depth_limit=12
  if [[ $rc -ne 0 ]]; then
    fail "asymmetry mannequin_head.off"
  else
    for text in "orientation auto" "rho_d" "deg apart" "lower_third"; do
      grep -qF -- "$text" "$tmp/stdout" || fail "asymmetry mannequin_head.off: no '$text'"
    done
  fi
fi

# --- indices by region, the points, a cohort and its norms, test-retest ---
printf '2 -8\n7 -8\n7 -2\n2 -2\n' >"$tmp/cheek.txt"
cohort=$tmp/cohort
mkdir "$cohort"
python3 - configs/data/face_a.xyz "$cohort" <<'PY'
import random, sys
points = [tuple(map(float, l.split()[:3])) for l in open(sys.argv[1]) if l.strip() and l[0] != "#"]
for k in range(3):
    rng = random.Random(k)
    with open("%s/scan%d.xyz" % (sys.argv[2], k), "w") as f:
        for x, y, z in points:
            f.write("%.6f %.6f %.6f\n" % (x, y, z + rng.gauss(0, 0.05)))
PY
run asymmetry "$cohort" --csv="$good/cohort.csv"
[[ $rc -eq 0 ]] || fail "asymmetry FOLDER --csv"
[[ $(grep -c "^asymmetry: face" "$tmp/stderr") -eq 3 ]] || fail "asymmetry FOLDER: expected a progress line per face"
run asymmetry "$cohort" --csv="$good/cohort_quiet.csv" --quiet
[[ $rc -eq 0 && ! -s $tmp/stderr ]] || fail "asymmetry FOLDER --quiet: stderr not empty"
# The faces side by side (one thread each) or one after another on one
# thread: the same table and printout.
cp "$tmp/stdout" "$tmp/cohort_stdout"
run asymmetry "$cohort" --csv="$good/cohort_one.csv" --quiet --threads=1
[[ $rc -eq 0 ]] && cmp -s "$good/cohort_one.csv" "$good/cohort_quiet.csv" &&
  cmp -s <(grep -v written "$tmp/stdout") <(grep -v written "$tmp/cohort_stdout") ||
  fail "asymmetry FOLDER: another table or printout on one thread"
# A face that cannot be read among others: its error, nothing written.
cp -r "$cohort" "$tmp/cohort_bad"
printf '1 2 3\n4 5 x\n' >"$tmp/cohort_bad/scan1b.xyz"
expect_error "scan1b.xyz:2" 1 asymmetry "$tmp/cohort_bad" --csv="$out/bad_cohort.csv" --quiet
[[ ! -e "$out/bad_cohort.csv" ]] || fail "asymmetry FOLDER with a bad face: a table was written"
run asymmetry configs/data/face_a.xyz --json --regions=cheek:"$tmp/cheek.txt" --norms="$good/cohort.csv" \
  --points="$good/points.csv" --units=mm
if [[ $rc -ne 0 ]]; then
  fail "asymmetry --regions --norms --points"
else
  python3 - "$tmp/stdout" "$good/points.csv" "$good/cohort.csv" "$good/cohort_quiet.csv" <<'PY' || fail "asymmetry: regions, z-scores, points, cohort"
import csv, json, math, statistics, sys
j = json.load(open(sys.argv[1]))
regions = j["regions"]
names = ["face", "upper_third", "middle_third", "lower_third", "left", "right", "cheek"]
assert list(regions) == names, list(regions)
for name in names:
    r = regions[name]
    for key in ("rms", "rms_sigma", "mean_abs", "mean_abs_sigma", "mean", "volume", "max_abs", "area", "nodes"):
        assert key in r and math.isfinite(r[key]), (name, key)
    assert 0 <= r["mean_abs"] <= r["rms"] <= r["max_abs"], (name, r)
    assert r["rms_sigma"] > 0, name
# The thirds and the halves each tile the overlap.
area = regions["face"]["area"]
assert abs(sum(regions[t]["area"] for t in names[1:4]) - area) < 1e-9 * area
assert abs(regions["left"]["area"] + regions["right"]["area"] - area) < 1e-9 * area
assert abs(regions["cheek"]["area"] - 30) < 1e-9, regions["cheek"]["area"]  # the square lies on the face
# ∫d² adds up over the thirds.
d2 = sum(regions[t]["rms"] ** 2 * regions[t]["area"] for t in names[1:4])
assert abs(d2 - regions["face"]["rms"] ** 2 * area) < 1e-9 * d2
assert len(j["thirds_y"]) == 4 and j["noise_sigma"] > 0 and set(j["plane_sigma"]) == {"tilt_y_deg", "tilt_z_deg", "offset"}
# z-scores against the cohort's table, by hand.
rows = list(csv.DictReader(open(sys.argv[3])))
assert len(rows) == 3 and open(sys.argv[3]).read() == open(sys.argv[4]).read()
for key in ("face_rms", "lower_third_rms", "left_mean"):
    values = [float(r[key]) for r in rows]
    name, stat = key.rsplit("_", 1) if not key.endswith("_mean") else (key[:-5], "mean")
    value = regions[name if stat != "rms" else key[:-4]]["rms" if stat == "rms" else "mean"]
    z = (value - statistics.mean(values)) / statistics.stdev(values)
    assert abs(j["z_scores"][key] - z) < 1e-6 * max(1, abs(z)), (key, j["z_scores"][key], z)
# The points: one row per face point, the face's RMS from them close to the region's.
points = list(csv.DictReader(open(sys.argv[2])))
assert len(points) == j["points"], (len(points), j["points"])
d = [float(p["difference"]) for p in points if p["difference"] != "nan"]
assert len(d) > 0.9 * len(points)
rms = math.sqrt(sum(v * v for v in d) / len(d))
assert abs(rms / regions["face"]["rms"] - 1) < 0.15, (rms, regions["face"]["rms"])
PY
fi
run asymmetry "$cohort/scan0.xyz" "$cohort/scan1.xyz" --json
if [[ $rc -ne 0 ]]; then
  fail "asymmetry SCAN1 SCAN2"
else
  python3 - "$tmp/stdout" <<'PY' || fail "asymmetry SCAN1 SCAN2: differences"
import json, sys
j = json.load(open(sys.argv[1]))
a, b = j["scans"]
for key, value in j["differences"].items():
    region, stat = ("_".join(key.split("_")[:-2]), "mean_abs") if key.endswith("_mean_abs") else \
                   ("_".join(key.split("_")[:-2]), "max_abs") if key.endswith("_max_abs") else key.rsplit("_", 1)
    expected = b["regions"][region][stat] - a["regions"][region][stat]
    assert abs(value - expected) < 1e-9 * max(1, abs(expected)), (key, value, expected)
assert abs(j["differences"]["face_rms"]) < 0.05, j["differences"]["face_rms"]
PY
fi

# --- bad input: exit 2, one line, nothing written ---
expect_error "--regions" 1 asymmetry configs/data/face_a.xyz --regions=cheek --output="$out/a.json"
expect_error "no_such_polygon.txt" 1 asymmetry configs/data/face_a.xyz --regions=c:"$tmp/no_such_polygon.txt" --output="$out/a.json"
expect_error "region 'c d'" 1 asymmetry configs/data/face_a.xyz --regions="c d:$tmp/cheek.txt" --output="$out/a.json"
expect_error "--points" 1 asymmetry configs/data/face_a.xyz --points="$out/p.txt" --output="$out/a.json"
expect_error "--map" 1 asymmetry "$cohort" --map="$out/m.png" --csv="$out/c.csv"
printf 'file,face_rms\na.xyz,0.5\nb.xyz,oops\n' >"$tmp/bad_norms.csv"
expect_error "bad_norms.csv:3" 1 asymmetry configs/data/face_a.xyz --norms="$tmp/bad_norms.csv" --output="$out/a.json"
expect_error "no_such_norms.csv" 1 asymmetry configs/data/face_a.xyz --norms="$tmp/no_such_norms.csv" --output="$out/a.json"
expect_error "too many arguments" 2 asymmetry "$cohort/scan0.xyz" "$cohort/scan1.xyz" "$cohort/scan2.xyz" --output="$out/a.json"
expect_error "no_such_face.xyz" 1 asymmetry "$tmp/no_such_face.xyz" --output="$out/a.json"
expect_error "--orientation" 1 asymmetry configs/data/face_a.xyz --orientation=sideways \
  --output="$out/a.json" "${map[@]/$good\/map.png/$out/m.png}"
expect_error "--depth_limit" 1 asymmetry configs/data/face_a.xyz --depth_limit=-1 --output="$out/a.json"
expect_error "--map" 1 asymmetry configs/data/face_a.xyz --map="$out/m.jpg" --output="$out/a.json"
expect_error "--output" 1 asymmetry configs/data/face_a.xyz --output="$out/missing/a.json" \
  "${map[@]/$good\/map.png/$out/m.png}"
printf '1 2 3\n4 5 6\n' >"$tmp/two_points.xyz"
expect_error "two_points.xyz" 1 asymmetry "$tmp/two_points.xyz" --output="$out/a.json"
# Usage errors also exit 2 (the error line, then the command's usage line).
expect_error "unknown flag" 2 asymmetry configs/data/face_a.xyz --bogus=1 --output="$out/a.json"
expect_error "missing FACE" 2 asymmetry --output="$out/a.json"

# The help synopsis names every flag asymmetry takes.
run help
for flag in --orientation --depth_limit --regions --map --points --csv --norms --units --json --output --quiet; do
  grep -q "asymmetry.*$flag" "$tmp/stdout" "$tmp/stderr" || fail "help: asymmetry synopsis lacks $flag"
done

if [[ $failures -ne 0 ]]; then
  echo "$failures failure(s)"
  exit 1
fi
echo "cli_asymmetry_test: all passed"

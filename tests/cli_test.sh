#!/usr/bin/env bash
# End-to-end tests of the surfreg program: outputs, exit codes and the
# one-line error contract.
# Usage: cli_test.sh SURFREG_BINARY PROJECT_SOURCE_DIR
set -u
if [[ $# -ne 2 ]]; then
  echo "usage: $0 SURFREG_BINARY PROJECT_SOURCE_DIR" >&2
  exit 2
fi
bin=$(realpath -- "$1") || exit 2
cd "$2" || exit 2  # paths below (and in messages) are relative to the project
data=tests/data/io
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
checks=0

fail() {
  echo "FAIL: $*"
  echo "  exit code: $rc"
  sed 's/^/  stdout: /' "$tmp/out" | head -20
  sed 's/^/  stderr: /' "$tmp/err" | head -20
  failures=$((failures + 1))
}

# Runs surfreg with the given arguments; sets rc, leaves $tmp/out and $tmp/err.
run() {
  checks=$((checks + 1))
  timeout 60 "$bin" "$@" >"$tmp/out" 2>"$tmp/err"
  rc=$?
}

# expect_input_error TEXT ARGS...: exit 2 and stderr is exactly one line,
# starting with "surfreg: error:" and containing TEXT.
expect_input_error() {
  local text=$1
  shift
  run "$@"
  local lines
  lines=$(wc -l <"$tmp/err")
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif [[ $lines -ne 1 ]]; then
    fail "surfreg $*: expected exactly one line on stderr, got $lines"
  elif ! head -1 "$tmp/err" | grep -q '^surfreg: error: '; then
    fail "surfreg $*: stderr does not start with 'surfreg: error: '"
  elif ! grep -qF -- "$text" "$tmp/err"; then
    fail "surfreg $*: stderr does not contain '$text'"
  elif [[ -s "$tmp/out" ]]; then
    fail "surfreg $*: expected no stdout"
  fi
}

# expect_usage_error ARGS...: exit 2, an error line and a usage text on stderr.
expect_usage_error() {
  run "$@"
  if [[ $rc -ne 2 ]]; then
    fail "surfreg $*: expected exit 2"
  elif ! head -1 "$tmp/err" | grep -q '^surfreg: error: '; then
    fail "surfreg $*: stderr does not start with 'surfreg: error: '"
  elif ! grep -q 'usage' "$tmp/err"; then
    fail "surfreg $*: no usage text on stderr"
  fi
}

# --- success ---------------------------------------------------------------

run triangulate configs/data/volcano.xyz
if [[ $rc -ne 0 ]]; then
  fail "triangulate volcano: expected exit 0"
elif ! grep -Eq '^input points: +5307$' "$tmp/out"; then
  fail "triangulate volcano: expected 'input points: 5307'"
elif ! grep -Eq '^origin: ' "$tmp/out" || ! grep -Eq '^triangles: +[1-9]' "$tmp/out"; then
  fail "triangulate volcano: expected the origin and a triangle count"
elif [[ -s "$tmp/err" ]]; then
  fail "triangulate volcano: expected a clean stderr"
fi

run triangulate configs/data/volcano.xyz --json
if [[ $rc -ne 0 ]]; then
  fail "triangulate --json: expected exit 0"
elif ! python3 -c '
import json, sys
r = json.load(sys.stdin)
assert r["file"] == "configs/data/volcano.xyz", r["file"]
assert r["n_points"] == 5307 and r["n_triangles"] > 0, r
assert r["n_vertices"] + r["n_duplicates"] == r["n_points"], r
assert r["n_hull_edges"] > 0 and len(r["origin"]) == 3, r
assert all(r["timings"][k] >= 0 for k in ("read", "triangulate", "total")), r
' <"$tmp/out"; then
  fail "triangulate --json: not the expected JSON object"
fi

# --threads: the same mesh and data domain on 1 and 2 threads (2.5e5
# points: the triangulation in slabs, stitched).
python3 -c '
import random
r = random.Random(5)
for _ in range(250000):
    x, y = r.uniform(0, 1000), r.uniform(0, 1000)
    print("%.4f %.4f %.4f" % (x, y, 0.01 * x + 0.02 * y + r.uniform(0, 1)))
' >"$tmp/big.xyz"
run triangulate "$tmp/big.xyz" --json --threads=1
cp "$tmp/out" "$tmp/one_thread.json"
run triangulate "$tmp/big.xyz" --json --threads=2
if [[ $rc -ne 0 ]] || ! python3 -c '
import json, sys
one, two = (json.load(open(f)) for f in sys.argv[1:])
for r in (one, two):
    del r["timings"], r["points_per_second"]
assert one == two and one["n_points"] == 250000, (one, two)
' "$tmp/one_thread.json" "$tmp/out"; then
  fail "triangulate --threads=1 and --threads=2: not the same mesh and domain"
fi
expect_input_error "flag '--threads' expects an integer >= 1, or all, got '0'" triangulate configs/data/volcano.xyz --threads=0

run --json triangulate "$data/square.off"  # flags may come first
if [[ $rc -ne 0 ]] || ! python3 -c '
import json, sys
r = json.load(sys.stdin)
assert r["n_points"] == 4 and r["n_triangles"] == 2 and r["n_hull_edges"] == 4, r
' <"$tmp/out"; then
  fail "--json triangulate square.off: expected 4 points, 2 triangles, 4 hull edges"
fi

for args in "help" "--help" "triangulate --help" "help triangulate"; do
  run $args
  if [[ $rc -ne 0 ]] || ! grep -q 'usage: surfreg' "$tmp/out" ||
     ! grep -q 'triangulate' "$tmp/out"; then
    fail "surfreg $args: expected a usage text on stdout and exit 0"
  fi
done

# `help COMMAND` lists the command's keys and flags (issue 23).
for spec in "align:--manifest: max_iterations: an integer" "measure:  volume: weights: lod:" \
            "sweep:  pairs:   --resume:" "jaw:  frames:" "triangulate:--domain:"; do
  command=${spec%%:*}
  run help "$command"
  for word in ${spec#*:}; do
    if [[ $rc -ne 0 ]] || ! grep -qF -- "$word" "$tmp/out"; then
      fail "surfreg help $command: expected '$word' in the help"
    fi
  done
done

# --- bad input: exit 2, one line naming the file (and line) ----------------

expect_input_error "$data/does_not_exist.xyz: cannot open: No such file or directory" \
  triangulate "$data/does_not_exist.xyz"
expect_input_error "$data/empty.xyz: no points" triangulate "$data/empty.xyz"
expect_input_error "$data/nan_line.xyz:5: z is NaN" triangulate "$data/nan_line.xyz"
expect_input_error "$data/bad_token.csv:3: y is not a number: '1O'" \
  triangulate "$data/bad_token.csv"
expect_input_error "$data/two_points.xyz: 2 points" triangulate "$data/two_points.xyz"
expect_input_error "$data/collinear.xyz: all points lie on one line" \
  triangulate "$data/collinear.xyz"
expect_input_error "$data/unknown.stl: unknown surface format '.stl'" \
  triangulate "$data/unknown.stl"
expect_input_error "$data/truncated.ply: file ends after 3 of 200 vertices" \
  triangulate "$data/truncated.ply"
expect_input_error "$data: no file extension" triangulate "$data"
mkdir "$tmp/dir.xyz"
expect_input_error "$tmp/dir.xyz: cannot read: Is a directory" triangulate "$tmp/dir.xyz"
head -c 4096 /dev/urandom >"$tmp/noise.ply"
expect_input_error "$tmp/noise.ply:1: not a PLY file" triangulate "$tmp/noise.ply"
cp "$tmp/noise.ply" "$tmp/noise.xyz"
expect_input_error "$tmp/noise.xyz" triangulate "$tmp/noise.xyz"

# --- bad usage: exit 2 with a usage text -------------------------------------

expect_usage_error frobnicate configs/data/volcano.xyz
expect_usage_error triangulate
expect_usage_error triangulate a.xyz b.xyz
expect_usage_error
run triangulate --no_such_flag configs/data/volcano.xyz
if [[ $rc -ne 2 ]] || ! grep -q "^surfreg: error: unknown flag '--no_such_flag'" "$tmp/err"; then
  fail "unknown flag: expected exit 2 and a clear message"
fi
# Mistakes get a suggestion (issue 23); help for no such command is an error.
expect_suggestion() {
  local text=$1
  shift
  run "$@"
  if [[ $rc -ne 2 ]] || ! head -1 "$tmp/err" | grep -qF -- "surfreg: error: $text"; then
    fail "surfreg $*: expected exit 2 and 'surfreg: error: $text'"
  fi
}
expect_suggestion "unknown command 'aling' (did you mean 'align'?)" aling a.xyz b.xyz
expect_suggestion "unknown flag '--max_iter=5' (did you mean '--max_iterations'?)" align a.xyz b.xyz --max_iter=5
expect_suggestion "unknown flag '--wieghts=uniform' (did you mean '--weights'?)" measure a.xyz b.xyz --wieghts=uniform
expect_suggestion "help: unknown command 'nothing' (commands: triangulate, measure, align, series, sweep" help nothing
run triangulate --json=maybe configs/data/volcano.xyz
if [[ $rc -ne 2 ]] || ! grep -q '^surfreg: error: bad value' "$tmp/err"; then
  fail "bad flag value: expected exit 2 and a clear message"
fi

# A flag of another command is refused, not silently ignored.
run measure configs/data/volcano.xyz configs/data/volcano.xyz --slope_weight=3
if [[ $rc -ne 2 ]] || ! grep -q "^surfreg: error: flag '--slope_weight' is not used by 'measure' (it is a flag of: align, series)" "$tmp/err"; then
  fail "another command's flag: expected exit 2 and a clear message"
fi
run triangulate configs/data/volcano.xyz --volume=union
if [[ $rc -ne 2 ]] || ! grep -q "^surfreg: error: flag '--volume' is not used by 'triangulate'" "$tmp/err"; then
  fail "another command's flag: expected exit 2 and a clear message"
fi
# glog's own flags are for every command; --json is triangulate's own.
run triangulate configs/data/volcano.xyz --minloglevel=1 --json
if [[ $rc -ne 0 ]]; then
  fail "triangulate with --minloglevel and --json: expected exit 0"
fi

# The cell kernel is a key: a named one aligns as the best does; a name
# that is no kernel is refused, naming the flag.
run align configs/data/face_a.xyz configs/data/face_b_moved.xyz --json --cell_kernel=scalar
if [[ $rc -ne 0 ]] || ! grep -q '"verdict": "converged_improved"' "$tmp/out"; then
  fail "--cell_kernel=scalar: expected a converged alignment"
fi
run align configs/data/face_a.xyz configs/data/face_b_moved.xyz --cell_kernel=bogus
if [[ $rc -ne 2 ]] || ! grep -q "flag '--cell_kernel' expects one of best, scalar, avx2, avx512, got 'bogus'" "$tmp/err"; then
  fail "--cell_kernel=bogus: expected exit 2 naming the flag"
fi

# More threads than cores: run on them, without Ceres's warning per solve.
run align configs/data/face_a.xyz configs/data/face_b_moved.xyz --json --threads=64
if [[ $rc -ne 0 ]] || grep -q "exceeds maximum available" "$tmp/err"; then
  fail "--threads=64: expected exit 0 and no warning from Ceres"
fi

echo "$((checks - failures)) of $checks checks passed"
[[ $failures -eq 0 ]]

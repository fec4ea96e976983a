# Sourced by tests/cli_measure_test.sh and cli_mask_test.sh (after
# cli_harness.sh): runs of `surfreg measure` and checks of their JSON.
# The sourcing script has set `tmp`, `bin`, `failures` and `checks`.

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

# Sourced by tests/cli_*_test.sh: run the surfreg binary and report failures.
# The sourcing script has set `tmp` (its scratch directory), `bin` (the
# binary), `failures` and `checks`; run leaves the exit code in `rc` and the
# outputs in $tmp/stdout and $tmp/stderr, which fail prints.

fail() {
  echo "FAIL: $*"
  echo "  exit code: ${rc:-none}"
  sed 's/^/  stdout: /' "$tmp/stdout" 2>/dev/null | head -20
  sed 's/^/  stderr: /' "$tmp/stderr" 2>/dev/null | head -20
  failures=$((failures + 1))
}

run() {
  checks=$((checks + 1))
  timeout 300 "$bin" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  rc=$?
  # Under ASan, LeakSanitizer's own tracer sometimes crashes while it stops
  # the threads at exit ("Tracer caught signal 11"): a failure of the
  # sanitizer's runtime, not a leak report nor an error of the program.
  # Such a run is run again; after two more crashes (on one lon/lat sweep it
  # crashed every time in CI), once more without the leak check: ASan's and
  # UBSan's own checks still apply.
  local again
  for again in 1 2 3; do
    [[ $rc -ne 0 ]] && grep -q "Tracer caught signal" "$tmp/stderr" 2>/dev/null || break
    if [[ $again -lt 3 ]]; then
      timeout 300 "$bin" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    else
      ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0" timeout 300 "$bin" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    fi
    rc=$?
  done
}

# has_part gdal|plots: whether this surfreg was built with that optional
# part (its --version says; tests/without_optional_parts_test.sh checks the
# refusals of a build without them).
has_part() {
  local version
  version=$("$bin" --version 2>&1)
  case $1 in
    gdal) [[ $version != *"built without GDAL"* ]] ;;
    plots) [[ $version != *"built without Cairo"* ]] ;;
    *) return 1 ;;
  esac
}

# expect_refused TEXT ARGS...: surfreg ARGS must exit 2 with one line on
# stderr that contains TEXT.
expect_refused() {
  local text=$1
  shift
  run "$@"
  checks=$((checks + 1))
  if [[ $rc -ne 2 || $(wc -l <"$tmp/stderr") -ne 1 ]] || ! grep -qF -- "$text" "$tmp/stderr"; then
    fail "surfreg $*: expected exit 2 and one line with: $text"
  fi
}

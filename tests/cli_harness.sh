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

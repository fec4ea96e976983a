# Sourced by the CI's sanitizer and without-optional-parts scripts: prints the ctest -E regex
# that matches exactly the tests named in tests/heavy_tests.txt.
heavy_tests_regex() {
  local names
  names=$(grep -v '^[[:space:]]*\(#\|$\)' "$1" | sed 's/[.[\*^$()+?{|]/\\&/g' | paste -sd '|')
  printf '^(%s)$' "$names"
}

#pragma once
// Helpers shared by the predicate tests (predicates_test.cc,
// predicates_incircle_test.cc, predicates_perturbed_test.cc): printing of
// point tuples, ulp steps and exactly cocircular lattice points. Nothing
// here calls measure/predicates.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "measure/surface.h"
#include "tests/testing/delaunay_checks.h"

namespace surfreg::testing {

inline std::string Str(const Point2& a, const Point2& b, const Point2& c) {
  return Str(a) + " " + Str(b) + " " + Str(c);
}
inline std::string Str(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  return Str(a, b, c) + " " + Str(d);
}

// x moved by k ulps (k < 0: down).
inline double Ulps(double x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, INFINITY);
  for (; k < 0; ++k) x = std::nextafter(x, -INFINITY);
  return x;
}

// Integer points exactly on the circle x² + y² = R² (R = 5, 25, 65 have many).
inline std::vector<std::pair<int, int>> LatticeCircle(int r) {
  std::vector<std::pair<int, int>> out;
  for (int x = -r; x <= r; ++x) {
    for (int y = -r; y <= r; ++y) {
      if (x * x + y * y == r * r) out.emplace_back(x, y);
    }
  }
  return out;
}

}  // namespace surfreg::testing

// InCircle against an independent exact oracle
// (tests/testing/exact_rational.h: dyadic rationals and the lifted 4x4
// determinant), and against analytic answers. Part of predicates_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "measure/predicates.h"
#include "tests/testing/exact_rational.h"
#include "tests/testing/predicate_oracle.h"

namespace surfreg {
namespace {

using testing::ExactInCirclePerturbedSign;
using testing::ExactInCircleSign;
using testing::ExactOrientSign;
using testing::LatticeCircle;
using testing::SignOf;
using testing::Str;
using testing::Ulps;

int CheckInCircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d,
                  int* reported) {
  const int expected = ExactInCircleSign(a, b, c, d);
  const double got = InCircle(a, b, c, d);
  if (SignOf(got) == expected) return 0;
  if ((*reported)++ < 5) {
    ADD_FAILURE() << "InCircle(" << Str(a, b, c, d) << ") = " << got << ", exact sign " << expected;
  }
  return 1;
}

// ---------------------------------------------------------------------------
// InCircle.

TEST(InCircleTest, AnalyticSigns) {
  const Point2 a{1, 0}, b{0, 1}, c{-1, 0};
  EXPECT_GT(InCircle(a, b, c, {0, 0}), 0.0);
  EXPECT_GT(InCircle(a, b, c, {0, -0.99}), 0.0);
  EXPECT_LT(InCircle(a, b, c, {0, -1.01}), 0.0);
  EXPECT_LT(InCircle(a, b, c, {5, 5}), 0.0);
  EXPECT_EQ(InCircle(a, b, c, {0, -1}), 0.0);
  // Clockwise a, b, c: sign flips.
  EXPECT_LT(InCircle(a, c, b, {0, 0}), 0.0);
  EXPECT_GT(InCircle(a, c, b, {5, 5}), 0.0);
}

TEST(InCircleTest, RandomPointsMatchExact) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int reported = 0, bad = 0;
  for (double scale : {1.0, 1e3, 1e-3, 1e30, 1e-30}) {
    for (int k = 0; k < 2000; ++k) {
      Point2 p[4];
      for (Point2& q : p) q = {scale * u(rng), scale * u(rng)};
      bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
    }
  }
  EXPECT_EQ(bad, 0);
}

TEST(InCircleTest, MixedMagnitudesMatchExact) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-20, 20);
  auto coord = [&]() { return std::ldexp(u(rng), e(rng)); };
  int reported = 0, bad = 0;
  for (int k = 0; k < 10000; ++k) {
    Point2 p[4];
    for (Point2& q : p) q = {coord(), coord()};
    bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
  }
  EXPECT_EQ(bad, 0);
}

// a, b, c, d on a circle (rounded cos/sin), d then moved by a few ulps: the
// exact answer hinges on the last bits.
TEST(InCircleTest, UlpPerturbedNearCocircularMatchExact) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), u(-1.0, 1.0);
  std::uniform_int_distribution<int> k(-3, 3);
  int reported = 0, bad = 0;
  for (int n = 0; n < 10000; ++n) {
    const double cx = (n % 3 == 0) ? 0.0 : 10.0 * u(rng), cy = (n % 3 == 0) ? 0.0 : 10.0 * u(rng);
    const double r = (n % 2 == 0) ? 1.0 : std::exp(3.0 * u(rng));
    Point2 p[4];
    double t[4];
    for (double& a : t) a = angle(rng);
    std::sort(t, t + 3);  // counter-clockwise a, b, c
    for (int i = 0; i < 4; ++i) p[i] = {cx + r * std::cos(t[i]), cy + r * std::sin(t[i])};
    p[3] = {Ulps(p[3].x, k(rng)), Ulps(p[3].y, k(rng))};
    bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
    bad += CheckInCircle(p[1], p[0], p[2], p[3], &reported);
  }
  EXPECT_EQ(bad, 0);
}

// Near-cocircular quadruples far from the origin with non-representable
// centres and radii: the coordinate differences are inexact, so the exact
// stage works on multi-component expansions. The counters show that the
// exact stage really runs.
TEST(InCircleTest, NearCocircularOffCentreStressMatchesExact) {
  std::mt19937_64 rng(30);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), u(-1.0, 1.0);
  std::uniform_int_distribution<int> k(-1, 1);
  const unsigned long long exact_before = ThreadPredicateCounters().incircle_exact;
  int reported = 0, bad = 0;
  const int cases = 20000;
  for (int n = 0; n < cases; ++n) {
    // Centre and radius of similar magnitude (2^-30 .. 2^30): the rounding
    // of the coordinates is then a tiny fraction of the radius.
    const int e = n % 61 - 30;
    const double cx = std::ldexp(u(rng), e), cy = std::ldexp(u(rng), e);
    const double r = std::ldexp(1.0 + u(rng) * 0.5, e - n % 3);
    Point2 p[4];
    for (Point2& q : p) {
      const double t = angle(rng);
      q = {cx + r * std::cos(t), cy + r * std::sin(t)};
    }
    p[3] = {Ulps(p[3].x, k(rng)), Ulps(p[3].y, k(rng))};
    bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
    bad += CheckInCircle(p[3], p[2], p[1], p[0], &reported);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(ThreadPredicateCounters().incircle_exact - exact_before, static_cast<unsigned long long>(cases / 4))
      << "the cases are meant to reach the exact stage";
}

// Integer points exactly on circles x² + y² = R² (LatticeCircle), moved to
// random integer centres; d also moved by single ulps.
TEST(InCircleTest, ExactlyCocircularReturnsZeroAndUlpNeighboursMatchExact) {
  std::mt19937_64 rng(24);
  int reported = 0, bad = 0, nonzero = 0;
  struct Frame {
    double cx, cy, step;
  };
  // Offsets where every lattice point is exact: plain, UTM-like with half
  // steps, and 1e15 where the spacing of doubles is 0.125.
  const Frame frames[] = {{0, 0, 1}, {12345, -678, 1}, {1e6, 5e6, 0.5}, {1e15, -3e15, 0.5}};
  for (int r : {5, 25, 65}) {
    const std::vector<std::pair<int, int>> circle = LatticeCircle(r);
    ASSERT_GE(circle.size(), 12u);
    for (const Frame& f : frames) {
      auto at = [&](std::pair<int, int> q) { return Point2{f.cx + f.step * q.first, f.cy + f.step * q.second}; };
      std::uniform_int_distribution<std::size_t> pick(0, circle.size() - 1);
      for (int n = 0; n < 300; ++n) {
        std::size_t i[4];
        for (std::size_t& j : i) j = pick(rng);
        if (std::set<std::size_t>(i, i + 4).size() < 4) continue;
        const Point2 a = at(circle[i[0]]), b = at(circle[i[1]]), c = at(circle[i[2]]), d = at(circle[i[3]]);
        ASSERT_EQ(ExactInCircleSign(a, b, c, d), 0);
        if (InCircle(a, b, c, d) != 0.0 && nonzero++ < 5) {
          ADD_FAILURE() << "InCircle(" << Str(a, b, c, d) << ") = " << InCircle(a, b, c, d)
                        << ", expected exactly 0";
        }
        for (int dx = -1; dx <= 1; ++dx) {
          for (int dy = -1; dy <= 1; ++dy) {
            // A zero coordinate stays: its ulp neighbours are subnormal.
            const Point2 e{d.x == 0.0 ? 0.0 : Ulps(d.x, dx), d.y == 0.0 ? 0.0 : Ulps(d.y, dy)};
            bad += CheckInCircle(a, b, c, e, &reported);
          }
        }
      }
    }
  }
  EXPECT_EQ(nonzero, 0);
  EXPECT_EQ(bad, 0);
}

// Integer points on two concentric circles x² + y² = R² and R² + 1 with
// R = 5·13·17·29·37·41 = 48612265 (~2^25.5): the points on the first come
// from products of Gaussian primes, (R, 1) is on the second. Analytically,
// d on the outer circle is outside the circle through a, b, c, so the sign
// is -orient(a, b, c); on the inner circle it is 0. The determinant is
// ~2^-51 of its scale: beyond the filter, and its exact integers reach ~2^110.
TEST(InCircleTest, ConcentricLatticeCirclesAnalytic) {
  const int64_t primes[6][2] = {{1, 2}, {2, 3}, {1, 4}, {2, 5}, {1, 6}, {4, 5}};  // a² + b² = p
  int64_t radius = 1;
  for (const auto& g : primes) radius *= g[0] * g[0] + g[1] * g[1];
  ASSERT_EQ(radius, 48612265);
  std::vector<Point2> on;
  for (int mask = 0; mask < 64; ++mask) {
    int64_t x = 1, y = 0;  // product of (a ± bi)², a Gaussian integer of norm R²
    for (int i = 0; i < 6; ++i) {
      const int64_t a = primes[i][0], b = (mask >> i & 1) ? -primes[i][1] : primes[i][1];
      const int64_t sx = a * a - b * b, sy = 2 * a * b;  // (a + bi)²
      const int64_t nx = x * sx - y * sy, ny = x * sy + y * sx;
      x = nx;
      y = ny;
    }
    ASSERT_EQ(x * x + y * y, radius * radius);
    on.push_back({static_cast<double>(x), static_cast<double>(y)});
    on.push_back({static_cast<double>(-y), static_cast<double>(x)});
  }
  const double r = static_cast<double>(radius);
  const std::vector<Point2> outer = {{r, 1}, {1, r}, {-r, 1}, {1, -r}, {-1, -r}};
  std::mt19937_64 rng(35);
  std::uniform_int_distribution<std::size_t> pick(0, on.size() - 1);
  int bad = 0, checked = 0;
  for (int n = 0; n < 3000; ++n) {
    const Point2 a = on[pick(rng)], b = on[pick(rng)], c = on[pick(rng)];
    const int orient = ExactOrientSign(a, b, c);
    if (orient == 0) continue;  // repeated point
    ++checked;
    const Point2 d = outer[n % outer.size()];
    const double got = InCircle(a, b, c, d);
    if (SignOf(got) != -orient && bad++ < 5) {
      ADD_FAILURE() << "InCircle(" << Str(a, b, c, d) << ") = " << got << ", expected sign " << -orient;
    }
    const Point2 e = on[pick(rng)];
    const double tie = InCircle(a, b, c, e);
    if (tie != 0.0 && bad++ < 5) {
      ADD_FAILURE() << "InCircle(" << Str(a, b, c, e) << ") = " << tie << ", expected 0 (cocircular)";
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(checked, 2000);
  // The oracle agrees with the analytic answer.
  EXPECT_EQ(ExactInCircleSign(on[0], on[10], on[20], outer[0]), -ExactOrientSign(on[0], on[10], on[20]));
}

TEST(InCircleTest, LargeOffsetsMatchExact) {
  std::mt19937_64 rng(25);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int reported = 0, bad = 0;
  for (double offset : {1e6, 4.5e6, 1e15}) {
    for (int n = 0; n < 3000; ++n) {
      Point2 p[4];
      for (Point2& q : p) q = {offset + 100.0 * u(rng), offset + 100.0 * u(rng)};
      bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
    }
  }
  EXPECT_EQ(bad, 0);
}

TEST(InCircleTest, TinyCoordinatesMatchExact) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : {1e-60, 1e-100, 1e-300}) {
    int reported = 0, bad = 0;
    for (int n = 0; n < 1000; ++n) {
      Point2 p[4];
      for (Point2& q : p) q = {scale * u(rng), scale * u(rng)};
      bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
    }
    EXPECT_EQ(bad, 0) << "scale " << scale;
  }
}

TEST(InCircleTest, HugeCoordinatesMatchExact) {
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : {1e80, 1e100, 1e150, 3e150}) {
    int reported = 0, bad = 0;
    for (int n = 0; n < 1000; ++n) {
      Point2 p[4];
      for (Point2& q : p) q = {scale * u(rng), scale * u(rng)};
      bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
    }
    EXPECT_EQ(bad, 0) << "scale " << scale;
  }
}

TEST(InCircleTest, WideMixedMagnitudesMatchExact) {
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-100, 100);
  auto coord = [&]() { return std::ldexp(u(rng), e(rng)); };
  int reported = 0, bad = 0;
  for (int k = 0; k < 3000; ++k) {
    Point2 p[4];
    for (Point2& q : p) q = {coord(), coord()};
    bad += CheckInCircle(p[0], p[1], p[2], p[3], &reported);
  }
  EXPECT_EQ(bad, 0);
}

// Small next to large within one call. predicates.h promises exactness
// unless "the components of one call span more than ~2^1000 (e.g. 1e-200
// next to 1e100)". Analytic case: a, b, c = (0,5), (-4,3), (4,-3) are
// counter-clockwise on x² + y² = 25 and d = (-5, y) with y != 0 has
// |d|² = 25 + y² > 25, so d is outside: InCircle < 0 for every y != 0. The
// same with everything scaled by 2^400 (still below the 2^500 limit).
void ExpectSmallNextToLargeOutside(const std::vector<int>& spans) {
  const Point2 a{0, 5}, b{-4, 3}, c{4, -3};
  for (int scale : {0, 400}) {
    for (int span : spans) {
      const Point2 sa{std::ldexp(a.x, scale), std::ldexp(a.y, scale)};
      const Point2 sb{std::ldexp(b.x, scale), std::ldexp(b.y, scale)};
      const Point2 sc{std::ldexp(c.x, scale), std::ldexp(c.y, scale)};
      const Point2 d{std::ldexp(-5.0, scale), std::ldexp(1.0, scale - span)};
      ASSERT_EQ(ExactInCircleSign(sa, sb, sc, d), -1);
      EXPECT_LT(InCircle(sa, sb, sc, d), 0.0)
          << "span 2^" << span << ": InCircle(" << Str(sa, sb, sc, d) << ") = " << InCircle(sa, sb, sc, d)
          << ", but d is outside (|d|^2 = R^2 + y^2)";
      EXPECT_EQ(InCirclePerturbed(sa, sb, sc, d), -1) << "span 2^" << span << " scale 2^" << scale;
    }
  }
}

TEST(InCircleTest, SmallNextToLargeUpToSpan2To500) {
  ExpectSmallNextToLargeOutside({10, 50, 100, 200, 300, 400, 500});
}

// Regression: from a span of ~2^532 on, InCircle returned 0 (y² underflowed
// inside the exact stage, which scaled the largest difference to 1). The
// exact stage now centres its range; this case stays exact to 2^700.
TEST(InCircleTest, SmallNextToLargeSpan2To540To700WithinDocumentedDomain) {
  ExpectSmallNextToLargeOutside({540, 600, 700});
}


// As for Orient2D (predicates_test.cc): scaling by 2^k scales the in-circle
// determinant by 2^4k > 0. Exactly cocircular lattice quadruples stay
// exactly 0 and their one-ulp neighbours keep their scale-1 signs.
TEST(InCircleTest, PowerOfTwoScalingKeepsExactSigns) {
  std::mt19937_64 rng(29);
  const std::vector<std::pair<int, int>> circle = LatticeCircle(65);
  std::uniform_int_distribution<std::size_t> pick(0, circle.size() - 1);
  std::vector<std::array<Point2, 4>> cases;
  while (cases.size() < 400) {
    std::size_t i[4];
    for (std::size_t& j : i) j = pick(rng);
    if (std::set<std::size_t>(i, i + 4).size() < 4) continue;
    std::array<Point2, 4> c;
    for (int j = 0; j < 4; ++j) {
      c[j] = {7.0 + circle[i[j]].first, -3.0 + circle[i[j]].second};
    }
    cases.push_back(c);
    const int dx = static_cast<int>(rng() % 3) - 1, dy = static_cast<int>(rng() % 3) - 1;
    c[3] = {Ulps(c[3].x, dx), Ulps(c[3].y, dy)};
    cases.push_back(c);
  }
  // Plus random integer quadruples: clear signs, which at the extreme scales
  // still reach the exact stage (the filter does not work there).
  std::uniform_int_distribution<int> coord(-3000, 3000);
  for (int n = 0; n < 200; ++n) {
    std::array<Point2, 4> c;
    for (Point2& q : c) q = {static_cast<double>(coord(rng)), static_cast<double>(coord(rng))};
    cases.push_back(c);
  }
  int bad = 0, zeros = 0;
  for (const auto& c : cases) zeros += ExactInCircleSign(c[0], c[1], c[2], c[3]) == 0 ? 1 : 0;
  // -272 .. -262 put the degree-4 products among the subnormals.
  for (int k : {-1000, -700, -400, -272, -268, -265, -262, -250, 200, 300, 440}) {
    for (const auto& c : cases) {
      Point2 q[4];
      for (int i = 0; i < 4; ++i) {
        q[i] = {std::ldexp(c[i].x, k), std::ldexp(c[i].y, k)};
        ASSERT_EQ(std::ldexp(q[i].x, -k), c[i].x);
        ASSERT_EQ(std::ldexp(q[i].y, -k), c[i].y);
      }
      const int expected = ExactInCircleSign(c[0], c[1], c[2], c[3]);
      const double got = InCircle(q[0], q[1], q[2], q[3]);
      if (SignOf(got) != expected && bad++ < 5) {
        ADD_FAILURE() << "scale 2^" << k << ": InCircle(" << Str(q[0], q[1], q[2], q[3]) << ") = " << got
                      << ", exact sign " << expected;
      }
      if (expected == 0) {
        const int perturbed = InCirclePerturbed(q[0], q[1], q[2], q[3]);
        if (perturbed != ExactInCirclePerturbedSign(c[0], c[1], c[2], c[3]) && bad++ < 5) {
          ADD_FAILURE() << "scale 2^" << k << ": InCirclePerturbed(" << Str(q[0], q[1], q[2], q[3])
                        << ") = " << perturbed;
        }
      }
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GE(zeros, 200);  // the 200 unperturbed ones, and unmoved neighbours
}

}  // namespace
}  // namespace surfreg

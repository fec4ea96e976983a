// Orient2D against an independent exact oracle
// (tests/testing/exact_rational.h: big-integer dyadic rationals), and against
// analytic answers; and the oracle itself. InCircle is tested in
// predicates_incircle_test.cc, InCirclePerturbed and its tie rule in
// predicates_perturbed_test.cc (the same test program).
#include "measure/predicates.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "tests/testing/exact_rational.h"
#include "tests/testing/predicate_oracle.h"

namespace surfreg {
namespace {

using testing::BigInt;
using testing::Dyadic;
using testing::ExactInCircleSign;
using testing::ExactOrientDet;
using testing::ExactOrientSign;
using testing::SignOf;
using testing::Str;
using testing::Ulps;

// Compares Orient2D with the exact oracle; returns the number of mismatches
// (the first few are reported).
int CheckOrient(const Point2& a, const Point2& b, const Point2& c, int* reported) {
  const int expected = ExactOrientSign(a, b, c);
  const double got = Orient2D(a, b, c);
  if (SignOf(got) == expected) return 0;
  if ((*reported)++ < 5) {
    ADD_FAILURE() << "Orient2D(" << Str(a, b, c) << ") = " << got << ", exact sign " << expected;
  }
  return 1;
}

// ---------------------------------------------------------------------------
// The oracle itself, against independent truth (__int128 and hand values).

__extension__ typedef __int128 Int128;  // GCC/Clang extension, as a reference

TEST(ExactOracleTest, BigIntMatchesInt128) {
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<int64_t> u(-(int64_t{1} << 62), int64_t{1} << 62);
  for (int k = 0; k < 2000; ++k) {
    const int64_t a = u(rng) >> (rng() % 60), b = u(rng) >> (rng() % 60);
    const Int128 sum = static_cast<Int128>(a) + b, diff = static_cast<Int128>(a) - b;
    const Int128 prod = static_cast<Int128>(a) * b;
    const BigInt A = BigInt::FromInt64(a), B = BigInt::FromInt64(b);
    auto to_big = [](Int128 v) {
      // v = hi * 2^62 + lo with |lo| < 2^62.
      const auto lo = static_cast<int64_t>(v % (static_cast<Int128>(1) << 62));
      const auto hi = static_cast<int64_t>(v / (static_cast<Int128>(1) << 62));
      return BigInt::FromInt64(hi).ShiftLeft(62) + BigInt::FromInt64(lo);
    };
    ASSERT_TRUE((A + B) == to_big(sum)) << a << " + " << b;
    ASSERT_TRUE((A - B) == to_big(diff)) << a << " - " << b;
    ASSERT_TRUE((A * B) == to_big(prod)) << a << " * " << b;
    ASSERT_EQ((A * B).Sign(), prod > 0 ? 1 : (prod < 0 ? -1 : 0));
  }
  EXPECT_EQ(BigInt::FromInt64(INT64_MIN).ToHex(), "-0x8000000000000000");
  EXPECT_EQ(BigInt::FromInt64(1).ShiftLeft(100).ToHex(), "0x10000000000000000000000000");
}

TEST(ExactOracleTest, DyadicIsExact) {
  // 0.1 + 0.2 != 0.3 exactly, but (0.1 + 0.2 rounded) is what doubles give.
  const Dyadic a = Dyadic::FromDouble(0.1), b = Dyadic::FromDouble(0.2);
  EXPECT_TRUE((a + b) != Dyadic::FromDouble(0.3));
  EXPECT_TRUE((a + b) != Dyadic::FromDouble(0.1 + 0.2));
  // 2^-1074 (smallest subnormal) and 2^1023 survive.
  const Dyadic tiny = Dyadic::FromDouble(std::ldexp(1.0, -1074));
  const Dyadic huge = Dyadic::FromDouble(std::ldexp(1.0, 1023));
  EXPECT_TRUE((tiny * huge) == Dyadic::FromDouble(std::ldexp(1.0, -51)));
  EXPECT_EQ((huge - huge).Sign(), 0);
  EXPECT_EQ((tiny - Dyadic::FromDouble(0.0)).Sign(), 1);
  // x*x - (x*x rounded) is the (non-zero) rounding error.
  const double x = 1.0 + std::ldexp(1.0, -30);
  const Dyadic X = Dyadic::FromDouble(x);
  EXPECT_NE((X * X - Dyadic::FromDouble(x * x)).Sign(), 0);
  EXPECT_TRUE(X * X == Dyadic::FromDouble(1.0 + std::ldexp(1.0, -29)) +
                           Dyadic::FromDouble(std::ldexp(1.0, -60)));
}

TEST(ExactOracleTest, AnalyticSigns) {
  const Point2 o{0, 0}, ex{1, 0}, ey{0, 1};
  EXPECT_EQ(ExactOrientSign(o, ex, ey), 1);
  EXPECT_EQ(ExactOrientSign(o, ey, ex), -1);
  EXPECT_EQ(ExactOrientSign(o, ex, {2, 0}), 0);
  // Twice the area of (0,0) (3,0) (0,4) is 12.
  EXPECT_TRUE(ExactOrientDet(o, {3, 0}, {0, 4}) == Dyadic::FromInt(12));
  // Unit circle through (1,0), (0,1), (-1,0), counter-clockwise.
  const Point2 a{1, 0}, b{0, 1}, c{-1, 0};
  EXPECT_EQ(ExactInCircleSign(a, b, c, o), 1);
  EXPECT_EQ(ExactInCircleSign(a, b, c, {2, 0}), -1);
  EXPECT_EQ(ExactInCircleSign(a, b, c, {0, -1}), 0);
  EXPECT_EQ(ExactInCircleSign(a, c, b, o), -1);  // clockwise flips
  // (0.6, -0.8) is not on the circle in binary: 0.6 rounds down by ~2.2e-17
  // and 0.8 up by ~4.4e-17, so x² + y² - 1 ~ -2(0.6)(2.2e-17) + 2(0.8)(4.4e-17)
  // > 0: just outside.
  EXPECT_EQ(ExactInCircleSign(a, b, c, {0.6, -0.8}), -1);
  EXPECT_EQ(ExactInCircleSign(a, b, c, {0.5, -0.75}), 1);
}

// ---------------------------------------------------------------------------
// Orient2D.

TEST(Orient2DTest, AnalyticSigns) {
  EXPECT_GT(Orient2D({0, 0}, {1, 0}, {0, 1}), 0.0);
  EXPECT_LT(Orient2D({0, 0}, {0, 1}, {1, 0}), 0.0);
  EXPECT_EQ(Orient2D({0, 0}, {1, 1}, {3, 3}), 0.0);
  EXPECT_EQ(Orient2D({1, 1}, {1, 1}, {5, -2}), 0.0);  // repeated point
  // Magnitude: twice the signed area (approximate in general, exact here).
  EXPECT_DOUBLE_EQ(Orient2D({0, 0}, {3, 0}, {0, 4}), 12.0);
}

TEST(Orient2DTest, RandomPointsMatchExact) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int reported = 0, bad = 0;
  for (double scale : {1.0, 1e-3, 1e3, 1e20, 1e-20}) {
    for (int k = 0; k < 3000; ++k) {
      const Point2 a{scale * u(rng), scale * u(rng)}, b{scale * u(rng), scale * u(rng)},
          c{scale * u(rng), scale * u(rng)};
      bad += CheckOrient(a, b, c, &reported);
    }
  }
  EXPECT_EQ(bad, 0);
}

// Coordinates with independent random exponents (2^-40 .. 2^40): products of
// very different magnitudes meet in one sum.
TEST(Orient2DTest, MixedMagnitudesMatchExact) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-40, 40);
  auto coord = [&]() { return std::ldexp(u(rng), e(rng)); };
  int reported = 0, bad = 0;
  for (int k = 0; k < 20000; ++k) {
    const Point2 a{coord(), coord()}, b{coord(), coord()}, c{coord(), coord()};
    bad += CheckOrient(a, b, c, &reported);
  }
  EXPECT_EQ(bad, 0);
}

// The classic failure case of naive orientation (Kettner et al., "Classroom
// examples of robustness problems"): p moved over a 64 x 64 block of ulps
// near the line y = x through q and r.
TEST(Orient2DTest, UlpGridNearLineYEqualsX) {
  int reported = 0, bad = 0, zeros = 0;
  const std::array<std::array<Point2, 3>, 3> cases = {{
      {{{0.5, 0.5}, {12, 12}, {24, 24}}},
      {{{0.5, 0.5}, {17.300000000000001, 17.300000000000001}, {24.00000000000005, 24.0000000000000053}}},
      {{{0.5, 0.5}, {8.8000000000000007, 8.8000000000000007}, {12.1, 12.1}}},
  }};
  for (const auto& cs : cases) {
    for (int i = 0; i < 64; ++i) {
      for (int j = 0; j < 64; ++j) {
        const Point2 p{Ulps(cs[0].x, i), Ulps(cs[0].y, j)};
        zeros += ExactOrientSign(p, cs[1], cs[2]) == 0 ? 1 : 0;
        bad += CheckOrient(p, cs[1], cs[2], &reported);
        bad += CheckOrient(cs[1], p, cs[2], &reported);
        bad += CheckOrient(cs[2], cs[1], p, &reported);
      }
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(zeros, 0);  // the block straddles the line: exact zeros occur
}

// Three points on y = x, each coordinate moved by -3..3 ulps at random.
TEST(Orient2DTest, UlpPerturbedCollinearMatchExact) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  std::uniform_int_distribution<int> k(-3, 3);
  int reported = 0, bad = 0, zeros = 0;
  for (int n = 0; n < 20000; ++n) {
    Point2 p[3];
    for (Point2& q : p) {
      const double t = u(rng);
      q = {Ulps(t, k(rng)), Ulps(t, k(rng))};
    }
    zeros += ExactOrientSign(p[0], p[1], p[2]) == 0 ? 1 : 0;
    bad += CheckOrient(p[0], p[1], p[2], &reported);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(zeros, 0);
}

// c = a + t (b - a) rounded, then moved by a few ulps: the sign depends on
// bits far below the inputs' magnitude.
TEST(Orient2DTest, NearlyCollinearRandomLinesMatchExact) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> k(-2, 2);
  int reported = 0, bad = 0;
  for (int n = 0; n < 20000; ++n) {
    const Point2 a{u(rng), u(rng)}, b{u(rng) * 1e3, u(rng) * 1e-3};
    const double t = 4.0 * u(rng);
    const Point2 c{Ulps(a.x + t * (b.x - a.x), k(rng)), Ulps(a.y + t * (b.y - a.y), k(rng))};
    bad += CheckOrient(a, b, c, &reported);
    bad += CheckOrient(c, a, b, &reported);
  }
  EXPECT_EQ(bad, 0);
}

TEST(Orient2DTest, LargeOffsetsMatchExact) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> k(-4, 4);
  int reported = 0, bad = 0;
  // ~1e6 + small values (UTM-like), and nearly collinear ones.
  for (int n = 0; n < 10000; ++n) {
    const Point2 a{1e6 + u(rng), 1e6 + u(rng)}, b{1e6 + u(rng), 1e6 + u(rng)};
    const Point2 c{1e6 + u(rng), 1e6 + u(rng)};
    bad += CheckOrient(a, b, c, &reported);
    const double t = u(rng);
    const Point2 d{Ulps(a.x + t * (b.x - a.x), k(rng)), Ulps(a.y + t * (b.y - a.y), k(rng))};
    bad += CheckOrient(a, b, d, &reported);
  }
  // ~1e15, where the spacing of doubles is 0.125.
  std::uniform_int_distribution<int> s(-1000, 1000);
  for (int n = 0; n < 10000; ++n) {
    Point2 p[3];
    for (Point2& q : p) q = {1e15 + 0.125 * s(rng), 1e15 + 0.125 * s(rng)};
    bad += CheckOrient(p[0], p[1], p[2], &reported);
  }
  EXPECT_EQ(bad, 0);
}

TEST(Orient2DTest, ExactlyCollinearReturnsZero) {
  std::mt19937_64 rng(16);
  std::uniform_int_distribution<int64_t> base(-(int64_t{1} << 26), int64_t{1} << 26);
  std::uniform_int_distribution<int64_t> dir(-(int64_t{1} << 12), int64_t{1} << 12);
  std::uniform_int_distribution<int64_t> t(-(int64_t{1} << 12), int64_t{1} << 12);
  int nonzero = 0;
  for (int n = 0; n < 10000; ++n) {
    const int64_t px = base(rng), py = base(rng), dx = dir(rng), dy = dir(rng);
    const int64_t t1 = t(rng), t2 = t(rng), t3 = t(rng);
    const Point2 a{static_cast<double>(px + t1 * dx), static_cast<double>(py + t1 * dy)};
    const Point2 b{static_cast<double>(px + t2 * dx), static_cast<double>(py + t2 * dy)};
    const Point2 c{static_cast<double>(px + t3 * dx), static_cast<double>(py + t3 * dy)};
    ASSERT_EQ(ExactOrientSign(a, b, c), 0);
    if (Orient2D(a, b, c) != 0.0 && nonzero++ < 5) {
      ADD_FAILURE() << "Orient2D(" << Str(a, b, c) << ") = " << Orient2D(a, b, c) << ", expected 0";
    }
  }
  // The same lines offset to 1e15 (spacing 0.125) and 1e6 with half steps.
  for (int n = 0; n < 2000; ++n) {
    const int64_t dx = dir(rng) % 64, dy = dir(rng) % 64, t1 = t(rng) % 64, t2 = t(rng) % 64;
    const Point2 a{1e15, 2e15}, b{1e15 + 0.125 * t1 * dx, 2e15 + 0.25 * t1 * dy};
    const Point2 c{1e15 + 0.125 * t2 * dx, 2e15 + 0.25 * t2 * dy};
    ASSERT_EQ(ExactOrientSign(a, b, c), 0);
    if (Orient2D(a, b, c) != 0.0 && nonzero++ < 5) {
      ADD_FAILURE() << "Orient2D(" << Str(a, b, c) << ") = " << Orient2D(a, b, c) << ", expected 0";
    }
  }
  EXPECT_EQ(nonzero, 0);
}

// Tiny coordinates: the products underflow the double range (1e-300² =
// 1e-600), yet the determinant's sign is well defined.
TEST(Orient2DTest, TinyCoordinatesMatchExact) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : {1e-100, 1e-150, 1e-300}) {
    int reported = 0, bad = 0;
    for (int n = 0; n < 2000; ++n) {
      const Point2 a{scale * u(rng), scale * u(rng)}, b{scale * u(rng), scale * u(rng)},
          c{scale * u(rng), scale * u(rng)};
      bad += CheckOrient(a, b, c, &reported);
    }
    EXPECT_EQ(bad, 0) << "scale " << scale;
  }
}

// The documented domain: any finite coordinates below 2^500, with the
// components of one call spanning less than ~2^1000.
TEST(Orient2DTest, HugeCoordinatesMatchExact) {
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : {1e100, 1e150, 3e150}) {
    int reported = 0, bad = 0;
    for (int n = 0; n < 2000; ++n) {
      const Point2 a{scale * u(rng), scale * u(rng)}, b{scale * u(rng), scale * u(rng)},
          c{scale * u(rng), scale * u(rng)};
      bad += CheckOrient(a, b, c, &reported);
    }
    EXPECT_EQ(bad, 0) << "scale " << scale;
  }
}

TEST(Orient2DTest, WideMixedMagnitudesMatchExact) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-200, 200);
  auto coord = [&]() { return std::ldexp(u(rng), e(rng)); };
  int reported = 0, bad = 0;
  for (int k = 0; k < 5000; ++k) {
    const Point2 a{coord(), coord()}, b{coord(), coord()}, c{coord(), coord()};
    bad += CheckOrient(a, b, c, &reported);
  }
  EXPECT_EQ(bad, 0);
}

// Scaling every coordinate by 2^k is exact (no subnormals here) and scales
// the determinant by 2^2k > 0: the signs at scale 1 are the truth at every
// scale, down to where the products underflow and up to where they overflow.
TEST(Orient2DTest, PowerOfTwoScalingKeepsExactSigns) {
  std::vector<std::array<Point2, 3>> cases;
  for (int i = 0; i < 24; ++i) {
    for (int j = 0; j < 24; ++j) {
      cases.push_back({{{Ulps(0.5, i), Ulps(0.5, j)}, {12, 12}, {24, 24}}});
    }
  }
  std::mt19937_64 rng(20);
  std::uniform_int_distribution<int> small(-1000, 1000);
  for (int n = 0; n < 300; ++n) {  // exactly collinear integer triples
    const double px = small(rng), py = small(rng), dx = small(rng) % 30, dy = small(rng) % 30;
    const double t1 = small(rng) % 30, t2 = small(rng) % 30;
    cases.push_back({{{px, py}, {px + t1 * dx, py + t1 * dy}, {px + t2 * dx, py + t2 * dy}}});
  }
  int zeros = 0, bad = 0;
  for (const auto& c : cases) zeros += ExactOrientSign(c[0], c[1], c[2]) == 0 ? 1 : 0;
  // -540 .. -525 put the products among the subnormals (partial underflow).
  for (int k : {-1000, -800, -560, -540, -535, -530, -525, -300, 300, 450, 490}) {
    for (const auto& c : cases) {
      Point2 q[3];
      for (int i = 0; i < 3; ++i) {
        q[i] = {std::ldexp(c[i].x, k), std::ldexp(c[i].y, k)};
        ASSERT_EQ(std::ldexp(q[i].x, -k), c[i].x);
        ASSERT_EQ(std::ldexp(q[i].y, -k), c[i].y);
      }
      const int expected = ExactOrientSign(c[0], c[1], c[2]);
      const double got = Orient2D(q[0], q[1], q[2]);
      if (SignOf(got) != expected && bad++ < 5) {
        ADD_FAILURE() << "scale 2^" << k << ": Orient2D(" << Str(q[0], q[1], q[2]) << ") = " << got
                      << ", exact sign " << expected;
      }
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(zeros, 300);
}

TEST(Orient2DTest, NearCollinearOffsetStressMatchesExact) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> k(-1, 1);
  const unsigned long long exact_before = ThreadPredicateCounters().orient_exact;
  int reported = 0, bad = 0;
  const int cases = 30000;
  for (int n = 0; n < cases; ++n) {
    // Offset and direction of similar magnitude (2^-30 .. 2^30).
    const int e = n % 61 - 30;
    const double ox = std::ldexp(u(rng), e), oy = std::ldexp(u(rng), e);
    const double dx = std::ldexp(u(rng), e - n % 3), dy = std::ldexp(u(rng), e - n % 4);
    Point2 p[3];
    for (Point2& q : p) {
      const double t = 3.0 * u(rng);
      q = {Ulps(ox + t * dx, k(rng)), Ulps(oy + t * dy, k(rng))};
    }
    bad += CheckOrient(p[0], p[1], p[2], &reported);
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(ThreadPredicateCounters().orient_exact - exact_before, static_cast<unsigned long long>(cases / 4))
      << "the cases are meant to reach the exact stage";
}

// Small next to large within one call, as for InCircle
// (predicates_incircle_test.cc): (-2,-2), (4,4) and (0, 2^-k) turn
// counter-clockwise for every k (c is above the line y = x).
TEST(Orient2DTest, SmallNextToLargeWithinDocumentedDomain) {
  for (int scale : {0, 400}) {
    for (int span : {10, 100, 300, 500, 600, 700, 900, 990}) {
      const Point2 a{std::ldexp(-2.0, scale), std::ldexp(-2.0, scale)};
      const Point2 b{std::ldexp(4.0, scale), std::ldexp(4.0, scale)};
      const Point2 c{0.0, std::ldexp(1.0, scale - span)};
      ASSERT_EQ(ExactOrientSign(a, b, c), 1);
      EXPECT_GT(Orient2D(a, b, c), 0.0) << "span 2^" << span << " scale 2^" << scale << ": " << Str(a, b, c);
    }
  }
}


// ---------------------------------------------------------------------------
// Orient2DCentroidSign: the side of line ab the exact centroid of three
// points lies on, against the oracle sign(Σ exact Orient2D(a, b, c_i)).

int ExactCentroidSign(const Point2& a, const Point2& b, const Point2* c) {
  const testing::Dyadic sum =
      ExactOrientDet(a, b, c[0]) + ExactOrientDet(a, b, c[1]) + ExactOrientDet(a, b, c[2]);
  return sum.Sign();
}

// The centroid of (-4, 3), (-3, 2), (-3, 4) lies on the line through (-6, 5)
// and (-2, 2), the case the fuzzer found (measure_domain_test): exactly 0 in
// every frame shifted by whole units, while the rounded centroid is off the
// line in some of them (on either side).
TEST(Orient2DCentroidTest, CentroidOnTheLineIsZeroInEveryFrame) {
  int off_line[2] = {0, 0};
  for (int s = -64; s <= 64; ++s) {
    for (const double big : {0.0, 1e6, 4.5e15}) {
      const double dx = big + s, dy = 0.5 * big - 3 * s;
      const Point2 a{-6 + dx, 5 + dy}, b{-2 + dx, 2 + dy};
      const Point2 c[3] = {{-4 + dx, 3 + dy}, {-3 + dx, 2 + dy}, {-3 + dx, 4 + dy}};
      ASSERT_EQ(ExactCentroidSign(a, b, c), 0);  // whole units below 2^53: exact
      EXPECT_EQ(Orient2DCentroidSign(a, b, c), 0) << "shift " << dx << " " << dy;
      const Point2 g{(c[0].x + c[1].x + c[2].x) / 3.0, (c[0].y + c[1].y + c[2].y) / 3.0};
      const double rounded = Orient2D(a, b, g);
      if (rounded > 0.0) ++off_line[0];
      if (rounded < 0.0) ++off_line[1];
    }
  }
  EXPECT_GT(off_line[0], 0) << "the rounded centroid is never left of the line";
  EXPECT_GT(off_line[1], 0) << "the rounded centroid is never right of the line";
}

// Centroids within a few ulps of the line: three points on y = x (and on a
// line of another slope, offset far from the origin), each coordinate moved
// by -3..3 ulps, against the oracle.
TEST(Orient2DCentroidTest, NearTheLineMatchesExact) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  std::uniform_int_distribution<int> k(-3, 3);
  int bad = 0, zeros = 0, signs[2] = {0, 0};
  for (int n = 0; n < 20000; ++n) {
    const double ox = n % 2 ? 3.7e5 : 0.0, oy = n % 2 ? -6.1e6 : 0.0, slope = n % 3 ? 1.0 : 0.375;
    auto on_line = [&](double t) {
      return Point2{Ulps(ox + t, k(rng)), Ulps(oy + slope * t, k(rng))};
    };
    const Point2 a = on_line(u(rng)), b = on_line(u(rng));
    const Point2 c[3] = {on_line(u(rng)), on_line(u(rng)), on_line(u(rng))};
    const int expected = ExactCentroidSign(a, b, c);
    zeros += expected == 0;
    if (expected != 0) ++signs[expected > 0];
    const int got = Orient2DCentroidSign(a, b, c);
    if (got != expected && bad++ < 5) {
      ADD_FAILURE() << "Orient2DCentroidSign(" << Str(a, b, c[0]) << " " << testing::Str(c[1]) << " " << testing::Str(c[2])
                    << ") = " << got << ", exact " << expected;
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(zeros, 0);
  EXPECT_GT(signs[0], 0);
  EXPECT_GT(signs[1], 0);
}

// Random points far from degenerate: the filter decides, and agrees.
TEST(Orient2DCentroidTest, RandomPointsMatchExact) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int bad = 0;
  for (int n = 0; n < 5000; ++n) {
    const double scale = std::ldexp(1.0, static_cast<int>(rng() % 200) - 100);
    Point2 p[5];
    for (Point2& q : p) q = {scale * u(rng), scale * u(rng)};
    bad += Orient2DCentroidSign(p[0], p[1], p + 2) != ExactCentroidSign(p[0], p[1], p + 2);
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace surfreg

// Orient2D, InCircle and InCirclePerturbed against an independent exact
// oracle (tests/testing/exact_rational.h: big-integer dyadic rationals and
// the lifted 4x4 determinant), and against analytic answers.
#include "measure/predicates.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "tests/testing/delaunay_checks.h"
#include "tests/testing/exact_rational.h"

namespace surfreg {
namespace {

using testing::BigInt;
using testing::Dyadic;
using testing::ExactInCircleSign;
using testing::ExactInCirclePerturbedSign;
using testing::ExactOrientDet;
using testing::ExactOrientSign;
using testing::SignOf;

std::string Str(const Point2& p) { return testing::Str(p); }

std::string Str(const Point2& a, const Point2& b, const Point2& c) {
  return Str(a) + " " + Str(b) + " " + Str(c);
}
std::string Str(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  return Str(a, b, c) + " " + Str(d);
}

// x moved by k ulps (k < 0: down).
double Ulps(double x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, INFINITY);
  for (; k < 0; ++k) x = std::nextafter(x, -INFINITY);
  return x;
}

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

// Integer points exactly on circles x² + y² = R² (R = 5, 25, 65 have many),
// moved to random integer centres; d also moved by single ulps.
std::vector<std::pair<int, int>> LatticeCircle(int r) {
  std::vector<std::pair<int, int>> out;
  for (int x = -r; x <= r; ++x) {
    for (int y = -r; y <= r; ++y) {
      if (x * x + y * y == r * r) out.emplace_back(x, y);
    }
  }
  return out;
}

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

// Orient2D with the same kind of inputs: (-2,-2), (4,4) and (0, 2^-k) turn
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

// As for Orient2D: scaling by 2^k scales the in-circle determinant by
// 2^4k > 0. Exactly cocircular lattice quadruples stay exactly 0 and their
// one-ulp neighbours keep their scale-1 signs.
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

// ---------------------------------------------------------------------------
// InCirclePerturbed.

TEST(InCirclePerturbedTest, EqualsInCircleSignWhenNonZero) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0), angle(0.0, 2.0 * M_PI);
  std::uniform_int_distribution<int> k(-2, 2);
  int bad = 0;
  for (int n = 0; n < 20000; ++n) {
    Point2 p[4];
    if (n % 2 == 0) {
      for (Point2& q : p) q = {u(rng), u(rng)};
    } else {  // near-cocircular
      for (Point2& q : p) {
        const double t = angle(rng);
        q = {Ulps(std::cos(t), k(rng)), Ulps(std::sin(t), k(rng))};
      }
    }
    const int exact = ExactInCircleSign(p[0], p[1], p[2], p[3]);
    if (exact == 0) continue;
    const int got = InCirclePerturbed(p[0], p[1], p[2], p[3]);
    if (got != exact && bad++ < 5) {
      ADD_FAILURE() << "InCirclePerturbed(" << Str(p[0], p[1], p[2], p[3]) << ") = " << got
                    << ", exact in-circle sign " << exact;
    }
  }
  EXPECT_EQ(bad, 0);
}

// Exactly cocircular quadruples (lattice circles, also offset), in all 24
// argument orders: never 0; equal to the documented rule evaluated from its
// definition; an alternating function of its four arguments (it is the sign
// of the determinant of the perturbed lifted points, so every transposition
// flips it — in particular swapping a and b, and it is unchanged by the
// rotation (a, b, c) -> (b, c, a)).
TEST(InCirclePerturbedTest, CocircularQuadruplesFollowTheDocumentedRule) {
  std::mt19937_64 rng(32);
  int bad = 0;
  auto report = [&](const std::string& what) {
    if (bad++ < 8) ADD_FAILURE() << what;
  };
  const std::array<int, 4> identity = {0, 1, 2, 3};
  for (int r : {5, 25, 65}) {
    const std::vector<std::pair<int, int>> circle = LatticeCircle(r);
    std::uniform_int_distribution<std::size_t> pick(0, circle.size() - 1);
    for (double offset : {0.0, 1e6}) {
      for (int n = 0; n < 40; ++n) {
        std::size_t i[4];
        for (std::size_t& j : i) j = pick(rng);
        if (std::set<std::size_t>(i, i + 4).size() < 4) continue;
        Point2 p[4];
        for (int j = 0; j < 4; ++j) {
          p[j] = {offset + circle[i[j]].first, -offset + circle[i[j]].second};
        }
        std::array<int, 4> perm = identity;
        const int base = InCirclePerturbed(p[0], p[1], p[2], p[3]);
        do {
          const Point2 &a = p[perm[0]], &b = p[perm[1]], &c = p[perm[2]], &d = p[perm[3]];
          const int got = InCirclePerturbed(a, b, c, d);
          const int expected = ExactInCirclePerturbedSign(a, b, c, d);
          int inversions = 0;
          for (int x = 0; x < 4; ++x) {
            for (int y = x + 1; y < 4; ++y) inversions += perm[x] > perm[y] ? 1 : 0;
          }
          const int parity = inversions % 2 == 0 ? 1 : -1;
          if (got != 1 && got != -1) report("InCirclePerturbed(" + Str(a, b, c, d) + ") = " + std::to_string(got));
          if (got != expected) {
            report("InCirclePerturbed(" + Str(a, b, c, d) + ") = " + std::to_string(got) +
                   ", documented rule gives " + std::to_string(expected));
          }
          if (got != parity * base) {
            report("InCirclePerturbed not alternating: permutation of " + Str(p[0], p[1], p[2], p[3]) +
                   " with parity " + std::to_string(parity) + " gives " + std::to_string(got) +
                   ", identity gives " + std::to_string(base));
          }
          if (InCirclePerturbed(b, a, c, d) != -got) report("swap a,b does not flip: " + Str(a, b, c, d));
          if (InCirclePerturbed(b, c, a, d) != got) report("rotation changes result: " + Str(a, b, c, d));
        } while (std::next_permutation(perm.begin(), perm.end()));
      }
    }
  }
  EXPECT_EQ(bad, 0);
}

// Never 0 for four distinct points with a, b, c not collinear, and equal to
// the documented rule: every ordered quadruple of a 4 x 3 grid (many
// cocircular, many with d on a line through two of a, b, c).
TEST(InCirclePerturbedTest, NeverZeroOnDistinctPoints) {
  std::vector<Point2> grid;
  for (int x = 0; x < 4; ++x) {
    for (int y = 0; y < 3; ++y) grid.push_back({static_cast<double>(x), static_cast<double>(y)});
  }
  int bad = 0, mismatch = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    for (std::size_t j = 0; j < grid.size(); ++j) {
      for (std::size_t k = 0; k < grid.size(); ++k) {
        if (ExactOrientSign(grid[i], grid[j], grid[k]) == 0) continue;
        for (std::size_t l = 0; l < grid.size(); ++l) {
          if (l == i || l == j || l == k) continue;
          const int got = InCirclePerturbed(grid[i], grid[j], grid[k], grid[l]);
          if (got != 1 && got != -1 && bad++ < 5) {
            ADD_FAILURE() << "InCirclePerturbed(" << Str(grid[i], grid[j], grid[k], grid[l]) << ") = " << got;
          }
          const int expected = ExactInCirclePerturbedSign(grid[i], grid[j], grid[k], grid[l]);
          if (got != expected && mismatch++ < 5) {
            ADD_FAILURE() << "InCirclePerturbed(" << Str(grid[i], grid[j], grid[k], grid[l]) << ") = " << got
                          << ", documented rule gives " << expected;
          }
        }
      }
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(mismatch, 0);
}

// The four corners p0..p3 (counter-clockwise) of a square: with the
// perturbation they are in convex position and not cocircular, so exactly
// one diagonal has both its triangles locally Delaunay:
//   diagonal p0-p2: triangles (p0,p1,p2) and (p0,p2,p3), opposite p3 and p1;
//   diagonal p1-p3: triangles (p1,p2,p3) and (p1,p3,p0), opposite p0 and p2.
// Which one follows from the rule: the lexicographically largest corner is
// raised the most (dominantly), lifting it above the plane through the other
// three lifted corners, i.e. outside their circle; so the triangle of the
// other three is Delaunay and the chosen diagonal is the one that does not
// touch the largest corner. For an axis-aligned square (x0,y0)+(0|s, 0|s)
// the largest corner is (x0+s, y0+s): the diagonal (x0+s,y0)-(x0,y0+s).
TEST(InCirclePerturbedTest, SquareHasExactlyOneDelaunayDiagonal) {
  struct Square {
    Point2 p[4];
    int diagonal;  // expected: 0 for p0-p2, 1 for p1-p3
  };
  const double s2 = 0.5;
  const std::vector<Square> squares = {
      {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1},                   // largest (1,1) = p2
      {{{1, 0}, {1, 1}, {0, 1}, {0, 0}}, 0},                   // same square, rotated labels
      {{{1e6, 5e6}, {1e6 + s2, 5e6}, {1e6 + s2, 5e6 + s2}, {1e6, 5e6 + s2}}, 1},
      // A diamond: corners (1,0), (2,1), (1,2), (0,1); largest is (2,1) = p1.
      {{{1, 0}, {2, 1}, {1, 2}, {0, 1}}, 0},
      // A rotated square with integer corners (3,0), (4,3), (1,4), (0,1).
      {{{3, 0}, {4, 3}, {1, 4}, {0, 1}}, 0},  // largest (4,3) = p1
      // Not a square, on x² + y² = 25: the largest corner (5,0) = p0 and the
      // smallest (-3,-4) = p3 are adjacent, so this one also tells "largest
      // dominates" from "smallest dominates" (which would give p0-p2).
      {{{5, 0}, {4, 3}, {0, 5}, {-3, -4}}, 1},
  };
  for (const Square& sq : squares) {
    const Point2* p = sq.p;
    ASSERT_EQ(ExactInCircleSign(p[0], p[1], p[2], p[3]), 0);
    const bool d02 = InCirclePerturbed(p[0], p[1], p[2], p[3]) < 0 &&
                     InCirclePerturbed(p[0], p[2], p[3], p[1]) < 0;
    const bool d13 = InCirclePerturbed(p[1], p[2], p[3], p[0]) < 0 &&
                     InCirclePerturbed(p[1], p[3], p[0], p[2]) < 0;
    EXPECT_NE(d02, d13) << "square " << Str(p[0], p[1], p[2], p[3]) << ": diagonal p0-p2 "
                        << (d02 ? "" : "not ") << "Delaunay, p1-p3 " << (d13 ? "" : "not ") << "Delaunay";
    EXPECT_EQ(d13 ? 1 : 0, sq.diagonal) << "square " << Str(p[0], p[1], p[2], p[3]);
  }
}

// k exactly cocircular points (a convex polygon): the perturbed predicate
// must define one triangulation. By brute force, the triangles (i, j, l)
// with every other point outside under InCirclePerturbed must number k - 2,
// use each polygon edge once, and cover the polygon's area exactly.
TEST(InCirclePerturbedTest, CocircularPolygonIsTriangulatedConsistently) {
  for (int r : {5, 25, 65}) {
    std::vector<std::pair<int, int>> circle = LatticeCircle(r);
    std::vector<Point2> p;
    for (const auto& q : circle) p.push_back({static_cast<double>(q.first), static_cast<double>(q.second)});
    std::sort(p.begin(), p.end(), [](const Point2& a, const Point2& b) {
      return std::atan2(a.y, a.x) < std::atan2(b.y, b.x);
    });
    const int k = static_cast<int>(p.size());
    int count = 0;
    Dyadic area;
    std::vector<int> edge_use(static_cast<std::size_t>(k) * k, 0);
    for (int i = 0; i < k; ++i) {
      for (int j = i + 1; j < k; ++j) {
        for (int l = j + 1; l < k; ++l) {  // i < j < l in angle order: counter-clockwise
          bool empty = true;
          for (int m = 0; m < k && empty; ++m) {
            if (m != i && m != j && m != l) empty = InCirclePerturbed(p[i], p[j], p[l], p[m]) < 0;
          }
          if (!empty) continue;
          ++count;
          area = area + ExactOrientDet(p[i], p[j], p[l]);
          ++edge_use[i * k + j];
          ++edge_use[j * k + l];
          ++edge_use[i * k + l];
        }
      }
    }
    std::vector<int32_t> polygon(k);
    for (int i = 0; i < k; ++i) polygon[i] = i;
    EXPECT_EQ(count, k - 2) << "radius " << r << ", " << k << " cocircular points";
    EXPECT_TRUE(area == testing::TwiceArea(p, polygon)) << "radius " << r;
    for (int i = 0; i + 1 < k; ++i) {
      EXPECT_EQ(edge_use[i * k + (i + 1)], 1) << "polygon edge " << i;
    }
    EXPECT_EQ(edge_use[0 * k + (k - 1)], 1) << "polygon edge closing";
  }
}

}  // namespace
}  // namespace surfreg

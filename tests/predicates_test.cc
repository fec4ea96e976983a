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

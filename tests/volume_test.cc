// IntegrateGap, IntegrateGapWeighted and AbsVolumePaper against independent
// truths: values worked out by hand, a separate long-double implementation
// of the split-and-product-rule recipe (tests/testing/volume_reference.h),
// the symmetries of the integrals, and extreme values. Brute-force
// quadrature on actual triangles is in volume_quadrature_test.cc (the same
// test program).
#include "measure/volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "tests/testing/volume_reference.h"

namespace surfreg {
namespace {

using testing::PatternValues;
using testing::Reference;
using testing::RefResult;

constexpr double kEps = std::numeric_limits<double>::epsilon();

GapIntegrals Weighted(double area, std::array<double, 3> d, std::array<double, 3> m) {
  return IntegrateGapWeighted(area, d.data(), m.data());
}

void ExpectAll(const GapIntegrals& g, double abs, double above, double below, double signed_volume,
               double weight, double rel = 4 * kEps) {
  const double scale = std::max({std::fabs(abs), std::fabs(above), std::fabs(below)});
  EXPECT_NEAR(g.abs, abs, rel * std::fabs(abs));
  EXPECT_NEAR(g.above, above, rel * std::fabs(above));
  EXPECT_NEAR(g.below, below, rel * std::fabs(below));
  EXPECT_NEAR(g.signed_volume, signed_volume, rel * scale);
  EXPECT_NEAR(g.weight, weight, rel * std::fabs(weight));
}

void ExpectSame(const GapIntegrals& x, const GapIntegrals& y) {
  EXPECT_EQ(x.abs, y.abs);
  EXPECT_EQ(x.above, y.above);
  EXPECT_EQ(x.below, y.below);
  EXPECT_EQ(x.signed_volume, y.signed_volume);
  EXPECT_EQ(x.weight, y.weight);
}

// ---------------------------------------------------------------------------
// Hand-computed cases.

TEST(VolumeHandTest, AllPositive) {
  // S(1 + 2 + 3)/3 with S = 2.
  ExpectAll(IntegrateGap(2, 1, 2, 3), 4, 4, 0, 4, 2);
  EXPECT_DOUBLE_EQ(AbsVolumePaper(2, 1, 2, 3), 4);
}

TEST(VolumeHandTest, AllNegative) {
  ExpectAll(IntegrateGap(2, -1, -2, -3), 4, 0, 4, -4, 2);
  EXPECT_DOUBLE_EQ(AbsVolumePaper(2, -1, -2, -3), 4);
}

TEST(VolumeHandTest, LoneNegativeVertex) {
  // (1, -1, 1), S = 1: d = 0 at the midpoints of the two edges at b, so the
  // small triangle has area 1/4 and d from -1 to 0: below = 1/4 · 1/3 = 1/12.
  // The quadrilateral: triangle (X, a, c) of area 1/2 with d = (0, 1, 1),
  // 1/2 · 2/3 = 1/3, and triangle (X, c, Y) of area 1/4 with d = (0, 1, 0),
  // 1/12: above = 5/12. abs = 1/2 (the design's check), signed = 1/3.
  ExpectAll(IntegrateGap(1, 1, -1, 1), 0.5, 5.0 / 12, 1.0 / 12, 1.0 / 3, 1);
  EXPECT_NEAR(AbsVolumePaper(1, 1, -1, 1), 0.5, 2 * kEps);
  // And mirrored.
  ExpectAll(IntegrateGap(1, -1, 1, -1), 0.5, 1.0 / 12, 5.0 / 12, -1.0 / 3, 1);
}

TEST(VolumeHandTest, OneZeroTwoOpposite) {
  // (2, 0, -1), S = 3: d = 0 along the segment from b to X on edge a-c at
  // 2/3 of the way from a. Triangle (a, b, X): area 2, d = (2, 0, 0): 4/3.
  // Triangle (X, b, c): area 1, d = (0, 0, -1): 1/3.
  ExpectAll(IntegrateGap(3, 2, 0, -1), 5.0 / 3, 4.0 / 3, 1.0 / 3, 1, 3);
  EXPECT_NEAR(AbsVolumePaper(3, 2, 0, -1), 5.0 / 3, 4 * kEps);
  // (1, -1, 0), S = 1: two halves, d = (1, 0, 0) and (0, -1, 0): 1/6 each.
  ExpectAll(IntegrateGap(1, 1, -1, 0), 1.0 / 3, 1.0 / 6, 1.0 / 6, 0, 1);
  EXPECT_NEAR(AbsVolumePaper(1, 1, -1, 0), 1.0 / 3, 2 * kEps);
  EXPECT_NEAR(AbsVolumePaper(1, 0, 1, -1), 1.0 / 3, 2 * kEps);
}

TEST(VolumeHandTest, TwoZeros) {
  ExpectAll(IntegrateGap(1.5, 0, 0, 5), 2.5, 2.5, 0, 2.5, 1.5);
  ExpectAll(IntegrateGap(3, 0, -4, 0), 4, 0, 4, -4, 3);
  EXPECT_DOUBLE_EQ(AbsVolumePaper(3, 0, -4, 0), 4);
}

TEST(VolumeHandTest, AllZero) {
  const GapIntegrals g = IntegrateGap(7, 0, 0, 0);
  ExpectAll(g, 0, 0, 0, 0, 7);
  EXPECT_EQ(AbsVolumePaper(7, 0, 0, 0), 0);
  ExpectAll(Weighted(7, {0, 0, 0}, {1, 2, 3}), 0, 0, 0, 0, 14);
  ExpectAll(Weighted(7, {0, 0, 0}, {0, 0, 0}), 0, 0, 0, 0, 0);
  ExpectAll(IntegrateGap(0, 1, -2, 3), 0, 0, 0, 0, 0);
}

TEST(VolumeHandTest, NegativeZeroIsZero) {
  ExpectSame(IntegrateGap(1, -0.0, 1, -0.0), IntegrateGap(1, 0.0, 1, 0.0));
  ExpectAll(IntegrateGap(1, -0.0, 2, -1), IntegrateGap(1, 0, 2, -1).abs,
            IntegrateGap(1, 0, 2, -1).above, IntegrateGap(1, 0, 2, -1).below,
            IntegrateGap(1, 0, 2, -1).signed_volume, 1);
}

TEST(VolumeHandTest, AreaIsWeightWithoutWeights) {
  EXPECT_EQ(IntegrateGap(2.5, 1, -3, 0.25).weight, 2.5);
  EXPECT_NEAR(Weighted(2.5, {1, -3, 0.25}, {1, 1, 1}).weight, 2.5, 4 * kEps);
}

TEST(VolumeHandTest, WeightedConstantDifference) {
  // d = 2 constant, μ = (1, 2, 3), S = 1: 2 · mean(μ) = 2 · 2 = 4.
  ExpectAll(Weighted(1, {2, 2, 2}, {1, 2, 3}), 4, 4, 0, 4, 2);
  ExpectAll(Weighted(1, {-2, -2, -2}, {1, 2, 3}), 4, 0, 4, -4, 2);
}

TEST(VolumeHandTest, WeightedBarycentricSquare) {
  // d = μ = λ_a: ∫ λ² = 2S/12 = S/6.
  ExpectAll(Weighted(3, {1, 0, 0}, {1, 0, 0}), 0.5, 0.5, 0, 0.5, 1);
}

TEST(VolumeHandTest, WeightedSignChange) {
  // d = (1, -1, 1), S = 1, small triangle (b, X, Y) with X, Y the midpoints
  // of b-a and b-c, area 1/4, -d = (1, 0, 0) on it.
  // μ = λ_b = (0, 1, 0): μ on (b, X, Y) is (1, 1/2, 1/2), so
  //   below = (1/4)/12 · (1·1 + 1·2) = 1/16;
  //   signed = 1/12 · (Σ d_i m_i + Σd Σm) = 1/12 · (-1 + 1) = 0 = above - below.
  ExpectAll(Weighted(1, {1, -1, 1}, {0, 1, 0}), 1.0 / 8, 1.0 / 16, 1.0 / 16, 0, 1.0 / 3);
  // μ = λ_a = (1, 0, 0): μ on (b, X, Y) is (0, 1/2, 0), so
  //   below = (1/4)/12 · (0 + 1 · 1/2) = 1/96; signed = 1/12 · (1 + 1) = 1/6;
  //   above = 1/6 + 1/96 = 17/96.
  ExpectAll(Weighted(1, {1, -1, 1}, {1, 0, 0}), 18.0 / 96, 17.0 / 96, 1.0 / 96, 1.0 / 6,
            1.0 / 3);
  // By symmetry the same for λ_c; the three sum to μ = 1, the unweighted case.
  GapIntegrals sum = Weighted(1, {1, -1, 1}, {1, 0, 0});
  sum += Weighted(1, {1, -1, 1}, {0, 1, 0});
  sum += Weighted(1, {1, -1, 1}, {0, 0, 1});
  ExpectAll(sum, 0.5, 5.0 / 12, 1.0 / 12, 1.0 / 3, 1, 8 * kEps);
}

TEST(VolumeHandTest, WeightedUnitEqualsUnweighted) {
  std::mt19937_64 rng(11);
  for (int code = 0; code < 27; ++code) {
    for (int t = 0; t < 20; ++t) {
      const std::array<double, 3> d = PatternValues(rng, code);
      const GapIntegrals u = IntegrateGap(1.75, d[0], d[1], d[2]);
      ExpectAll(Weighted(1.75, d, {1, 1, 1}), u.abs, u.above, u.below, u.signed_volume, u.weight,
                8 * kEps);
      // A constant weight c scales everything by c.
      const GapIntegrals w = Weighted(1.75, d, {0.3, 0.3, 0.3});
      ExpectAll(w, 0.3 * u.abs, 0.3 * u.above, 0.3 * u.below, 0.3 * u.signed_volume,
                0.3 * u.weight, 8 * kEps);
    }
  }
}

TEST(VolumeHandTest, AccumulateSums) {
  GapIntegrals total;
  total += IntegrateGap(1, 1, -1, 1);
  total += IntegrateGap(2, 1, 2, 3);
  ExpectAll(total, 4.5, 4 + 5.0 / 12, 1.0 / 12, 4 + 1.0 / 3, 3);
}

// ---------------------------------------------------------------------------
// Identities and the independent long-double reference.

std::array<double, 3> RandomValues(std::mt19937_64& rng, int t) {
  // Mixed scales: exponents spread over ±8 decades, random signs, sometimes
  // an exact zero.
  std::uniform_real_distribution<double> u(0.5, 1), ex(-8, 8);
  std::uniform_int_distribution<int> sgn(0, 1), z(0, 9);
  std::array<double, 3> v{};
  for (int i = 0; i < 3; ++i) {
    v[i] = (sgn(rng) ? 1 : -1) * u(rng) * std::pow(10.0, t % 2 ? ex(rng) : 0.0);
    if (z(rng) == 0) v[i] = 0;
  }
  return v;
}

TEST(VolumeIdentityTest, PaperFormMatches) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> area(0.01, 100);
  for (int t = 0; t < 200000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, t);
    const double s = area(rng);
    const double paper = AbsVolumePaper(s, d[0], d[1], d[2]);
    const double abs = IntegrateGap(s, d[0], d[1], d[2]).abs;
    ASSERT_NEAR(paper, abs, 1e-13 * abs) << d[0] << " " << d[1] << " " << d[2];
  }
}

TEST(VolumeIdentityTest, PartsAddUp) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> area(0.01, 100), weight(0, 3);
  for (int t = 0; t < 200000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, t);
    const double s = area(rng);
    const GapIntegrals g = IntegrateGap(s, d[0], d[1], d[2]);
    const double scale = s * (std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2])) / 3;
    ASSERT_NEAR(g.abs, g.above + g.below, 2 * kEps * g.abs);
    ASSERT_NEAR(g.above - g.below, g.signed_volume, 16 * kEps * scale);
    ASSERT_GE(g.above, 0);
    ASSERT_GE(g.below, 0);

    std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
    if (t % 5 == 0) m[t % 3] = 0;
    const GapIntegrals w = Weighted(s, d, m);
    const double wscale =
        s / 12 *
        (std::fabs(d[0]) * m[0] + std::fabs(d[1]) * m[1] + std::fabs(d[2]) * m[2] +
         (std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2])) * (m[0] + m[1] + m[2]));
    ASSERT_NEAR(w.abs, w.above + w.below, 2 * kEps * w.abs);
    ASSERT_NEAR(w.above - w.below, w.signed_volume, 32 * kEps * wscale);
    ASSERT_GE(w.above, 0);
    ASSERT_GE(w.below, 0);
  }
}

TEST(VolumeIdentityTest, MatchesLongDoubleReference) {
  // The reference computes the pieces in long double along the other
  // diagonal of the quadrilateral; agreement to ~1e-14 relative checks the
  // regrouped closed forms of volume.cc term by term.
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> area(0.01, 100), weight(0, 3);
  for (int t = 0; t < 100000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, t);
    const double s = area(rng);
    std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
    if (t % 5 == 0) m[t % 3] = 0;
    for (bool weighted : {false, true}) {
      const std::array<double, 3> mm = weighted ? m : std::array<double, 3>{1, 1, 1};
      const GapIntegrals g = weighted ? Weighted(s, d, mm) : IntegrateGap(s, d[0], d[1], d[2]);
      const RefResult r = Reference(s, d, mm);
      const double rel = 1e-14;
      const double ref_abs = static_cast<double>(r.abs);
      ASSERT_NEAR(g.abs, ref_abs, rel * ref_abs);
      ASSERT_NEAR(g.above, static_cast<double>(r.above), rel * ref_abs);
      ASSERT_NEAR(g.below, static_cast<double>(r.below), rel * ref_abs);
      ASSERT_NEAR(g.signed_volume, static_cast<double>(r.signed_volume), rel * ref_abs);
      ASSERT_NEAR(g.weight, static_cast<double>(r.weight), rel * static_cast<double>(r.weight));
    }
  }
}

// ---------------------------------------------------------------------------
// Symmetries.

TEST(VolumeSymmetryTest, VertexPermutationsChangeNothing) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> weight(0, 3);
  for (int t = 0; t < 20000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, t);
    const std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
    const GapIntegrals g0 = IntegrateGap(1.3, d[0], d[1], d[2]);
    const GapIntegrals w0 = Weighted(1.3, d, m);
    const double paper0 = AbsVolumePaper(1.3, d[0], d[1], d[2]);
    std::array<int, 3> perm{0, 1, 2};
    while (std::next_permutation(perm.begin(), perm.end())) {
      const std::array<double, 3> dp{d[perm[0]], d[perm[1]], d[perm[2]]};
      const std::array<double, 3> mp{m[perm[0]], m[perm[1]], m[perm[2]]};
      ExpectSame(IntegrateGap(1.3, dp[0], dp[1], dp[2]), g0);
      ExpectSame(Weighted(1.3, dp, mp), w0);
      EXPECT_NEAR(AbsVolumePaper(1.3, dp[0], dp[1], dp[2]), paper0, 1e-14 * paper0);
    }
  }
}

TEST(VolumeSymmetryTest, NegationSwapsAboveAndBelow) {
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> weight(0, 3);
  for (int t = 0; t < 20000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, t);
    const std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
    for (bool weighted : {false, true}) {
      const std::array<double, 3> mm = weighted ? m : std::array<double, 3>{1, 1, 1};
      const GapIntegrals g = Weighted(0.7, d, mm);
      const GapIntegrals n = Weighted(0.7, {-d[0], -d[1], -d[2]}, mm);
      EXPECT_EQ(n.abs, g.abs);
      EXPECT_EQ(n.above, g.below);
      EXPECT_EQ(n.below, g.above);
      EXPECT_EQ(n.signed_volume, -g.signed_volume);
      EXPECT_EQ(n.weight, g.weight);
    }
    const GapIntegrals g = IntegrateGap(0.7, d[0], d[1], d[2]);
    const GapIntegrals n = IntegrateGap(0.7, -d[0], -d[1], -d[2]);
    EXPECT_EQ(n.abs, g.abs);
    EXPECT_EQ(n.above, g.below);
    EXPECT_EQ(n.below, g.above);
    EXPECT_EQ(n.signed_volume, -g.signed_volume);
  }
}

TEST(VolumeSymmetryTest, ScalingDifferencesAreaAndWeights) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> weight(0, 3), factor(0.01, 100);
  for (int t = 0; t < 20000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, t);
    const std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
    const GapIntegrals g = IntegrateGap(1.1, d[0], d[1], d[2]);
    const GapIntegrals w = Weighted(1.1, d, m);
    // Powers of two scale exactly.
    for (double k : {0.125, 1024.0, -4.0}) {
      const GapIntegrals gk = IntegrateGap(1.1, k * d[0], k * d[1], k * d[2]);
      const double ak = std::fabs(k);
      EXPECT_EQ(gk.abs, ak * g.abs);
      EXPECT_EQ(gk.above, k > 0 ? ak * g.above : ak * g.below);
      EXPECT_EQ(gk.below, k > 0 ? ak * g.below : ak * g.above);
      EXPECT_EQ(gk.signed_volume, k * g.signed_volume);
      const GapIntegrals gs = IntegrateGap(1.1 * ak, d[0], d[1], d[2]);
      EXPECT_EQ(gs.abs, ak * g.abs);
      EXPECT_EQ(gs.weight, ak * g.weight);
      const GapIntegrals wm = Weighted(1.1, d, {ak * m[0], ak * m[1], ak * m[2]});
      EXPECT_EQ(wm.abs, ak * w.abs);
      EXPECT_EQ(wm.above, ak * w.above);
      EXPECT_EQ(wm.weight, ak * w.weight);
    }
    // Any factor: to rounding.
    const double k = factor(rng);
    const GapIntegrals gk = IntegrateGap(1.1, k * d[0], k * d[1], k * d[2]);
    EXPECT_NEAR(gk.abs, k * g.abs, 8 * kEps * k * g.abs);
    EXPECT_NEAR(gk.above, k * g.above, 8 * kEps * k * g.abs);
    EXPECT_NEAR(gk.below, k * g.below, 8 * kEps * k * g.abs);
    const GapIntegrals gs = IntegrateGap(1.1 * k, d[0], d[1], d[2]);
    EXPECT_NEAR(gs.abs, k * g.abs, 4 * kEps * k * g.abs);
    EXPECT_NEAR(gs.above, k * g.above, 4 * kEps * k * g.abs);
    const GapIntegrals wk = Weighted(1.1, {k * d[0], k * d[1], k * d[2]}, m);
    EXPECT_NEAR(wk.abs, k * w.abs, 8 * kEps * k * w.abs);
    EXPECT_NEAR(wk.below, k * w.below, 8 * kEps * k * w.abs);
  }
}

// ---------------------------------------------------------------------------
// Extreme values.

// The split for one lone value l > 0 against p, q ≥ 0 (magnitudes), S = 1, in
// long double from the polynomial forms (all terms positive):
//   lone side  = l³ / (3(l + p)(l + q)),
//   other side = (l(p² + pq + q²) + pq(p + q)) / (3(l + p)(l + q)),
// the second being total - lone side = (p + q - l)/3 + lone side, expanded.
struct Sides {
  long double lone, other;
};
Sides ExactSides(long double l, long double p, long double q) {
  const long double den = 3 * (l + p) * (l + q);
  return {l * l * l / den, (l * (p * p + p * q + q * q) + p * q * (p + q)) / den};
}

void ExpectRel(double got, long double want, double rel) {
  EXPECT_TRUE(std::isfinite(got));
  EXPECT_NEAR(got, static_cast<double>(want), rel * std::fabs(static_cast<double>(want)))
      << "got " << got << " want " << static_cast<double>(want);
}

TEST(VolumeExtremeTest, TinyLoneValue) {
  // b = -1e-17 next to a = c = 1: the small triangle is ~1e-34 of S and its
  // volume ~3.3e-52; nothing may cancel it away or divide by zero.
  const GapIntegrals g = IntegrateGap(1, 1, -1e-17, 1);
  const long double b = 1e-17;  // the double nearest 1e-17, exactly
  const Sides e = ExactSides(b, 1, 1);
  ExpectRel(g.below, e.lone, 4 * kEps);
  ExpectRel(g.above, e.other, 4 * kEps);
  ExpectRel(g.abs, e.lone + e.other, 4 * kEps);
  ExpectRel(g.signed_volume, (2 - b) / 3, 4 * kEps);
  EXPECT_GT(g.below, 3.3e-52);
  EXPECT_LT(g.below, 3.4e-52);
  ExpectRel(AbsVolumePaper(1, 1, -1e-17, 1), e.lone + e.other, 4 * kEps);
  const GapIntegrals w = Weighted(1, {1, -1e-17, 1}, {1, 1, 1});
  ExpectRel(w.below, e.lone, 8 * kEps);
  ExpectRel(w.above, e.other, 8 * kEps);
}

TEST(VolumeExtremeTest, MagnitudesApartBy1e16) {
  // Lone value small: (1e16, -1, 1e16).
  {
    const GapIntegrals g = IntegrateGap(1, 1e16, -1, 1e16);
    const Sides e = ExactSides(1, 1e16L, 1e16L);
    ExpectRel(g.below, e.lone, 4 * kEps);  // ~3.3e-33
    ExpectRel(g.above, e.other, 4 * kEps);
    ExpectRel(AbsVolumePaper(1, 1e16, -1, 1e16), e.lone + e.other, 1e-14);
  }
  // Lone value large: (1, -1e16, 1). above = signed + below would cancel 16
  // digits here; the true above is (3e16 + 2)/(3(1e16 + 1)²) ≈ 1e-16.
  {
    const GapIntegrals g = IntegrateGap(1, 1, -1e16, 1);
    const Sides e = ExactSides(1e16L, 1, 1);
    ExpectRel(g.below, e.lone, 4 * kEps);
    ExpectRel(g.above, e.other, 4 * kEps);
    EXPECT_NEAR(g.above, 1e-16, 1e-18);
    ExpectRel(g.signed_volume, (2 - 1e16L) / 3, 4 * kEps);
    const GapIntegrals w = Weighted(1, {1, -1e16, 1}, {1, 1, 1});
    ExpectRel(w.above, e.other, 8 * kEps);
    ExpectRel(w.below, e.lone, 8 * kEps);
    // Weighted against the long-double reference.
    const RefResult r = Reference(1, {1, -1e16, 1}, {0.5, 2, 0});
    const GapIntegrals wr = Weighted(1, {1, -1e16, 1}, {0.5, 2, 0});
    ExpectRel(wr.above, r.above, 1e-14);
    ExpectRel(wr.below, r.below, 1e-14);
  }
  // Mixed: one zero beside values 1e16 apart.
  {
    const GapIntegrals g = IntegrateGap(1, 1e-8, 0, -1e8);
    const Sides e = ExactSides(static_cast<long double>(1e-8), 0, 1e8L);
    ExpectRel(g.above, e.lone, 4 * kEps);
    ExpectRel(g.below, e.other, 4 * kEps);
  }
}

TEST(VolumeExtremeTest, TinyScale) {
  // Everything at the 1e-300 scale equals the unit-scale result times 1e-300
  // (values only; with S = 1 the results stay normal).
  std::mt19937_64 rng(13);
  for (int t = 0; t < 2000; ++t) {
    const std::array<double, 3> d = RandomValues(rng, 0);
    const GapIntegrals g = IntegrateGap(2, d[0], d[1], d[2]);
    const GapIntegrals s = IntegrateGap(2, 1e-300 * d[0], 1e-300 * d[1], 1e-300 * d[2]);
    const double tol = 8 * kEps * 1e-300 * g.abs;
    EXPECT_NEAR(s.abs, 1e-300 * g.abs, tol);
    EXPECT_NEAR(s.above, 1e-300 * g.above, tol);
    EXPECT_NEAR(s.below, 1e-300 * g.below, tol);
    EXPECT_NEAR(AbsVolumePaper(2, 1e-300 * d[0], 1e-300 * d[1], 1e-300 * d[2]), 1e-300 * g.abs,
                1e-13 * 1e-300 * g.abs);
    const GapIntegrals w = Weighted(2, {1e-300 * d[0], 1e-300 * d[1], 1e-300 * d[2]}, {1, 2, 0});
    const GapIntegrals w1 = Weighted(2, d, {1, 2, 0});
    EXPECT_NEAR(w.abs, 1e-300 * w1.abs, 8 * kEps * 1e-300 * w1.abs);
    EXPECT_NEAR(w.below, 1e-300 * w1.below, 8 * kEps * 1e-300 * w1.abs);
  }
  // (1e-300, -1e-300, 1e-300): |b|³ = 1e-900 would underflow; the answer is
  // 1e-300 times that of (1, -1, 1).
  const GapIntegrals g = IntegrateGap(1, 1e-300, -1e-300, 1e-300);
  EXPECT_NEAR(g.below, 1e-300 / 12, 4 * kEps * 1e-300);
  EXPECT_NEAR(g.abs, 0.5e-300, 4 * kEps * 1e-300);
  EXPECT_NEAR(AbsVolumePaper(1, 1e-300, -1e-300, 1e-300), 0.5e-300, 4 * kEps * 1e-300);
}

TEST(VolumeExtremeTest, SubnormalAndHugeStayFinite) {
  const double den = std::numeric_limits<double>::denorm_min();
  const std::array<std::array<double, 3>, 6> cases{{{den, -den, den},
                                                    {1e-310, -5e-324, 1},
                                                    {0, -den, 1e300},
                                                    {1e300, -1e300, 1e300},
                                                    {-1e307, 1e-307, 1e307},
                                                    {1e-320, 0, -1e-320}}};
  for (const auto& d : cases) {
    for (double s : {1.0, 1e-10}) {
      const GapIntegrals g = IntegrateGap(s, d[0], d[1], d[2]);
      const GapIntegrals w = Weighted(s, d, {1, 0.5, 2});
      for (const GapIntegrals& x : {g, w}) {
        EXPECT_TRUE(std::isfinite(x.abs) && std::isfinite(x.above) && std::isfinite(x.below) &&
                    std::isfinite(x.signed_volume))
            << d[0] << " " << d[1] << " " << d[2];
        EXPECT_GE(x.above, 0);
        EXPECT_GE(x.below, 0);
        EXPECT_LE(x.above, x.abs);
        EXPECT_LE(x.below, x.abs);
      }
      EXPECT_TRUE(std::isfinite(AbsVolumePaper(s, d[0], d[1], d[2])));
    }
  }
  // (1e300, -1e300, 1e300): 1e300 times (1, -1, 1).
  const GapIntegrals h = IntegrateGap(1, 1e300, -1e300, 1e300);
  EXPECT_NEAR(h.abs, 0.5e300, 4 * kEps * 1e300);
  EXPECT_NEAR(h.below, 1e300 / 12, 4 * kEps * 1e300);
  // The smallest subnormals: (den, -den, den) with S = 12 is den times
  // (6, 5, 1) for (abs, above, below); below the normal range the results
  // are only near that, within a few units of den (intermediate products
  // such as den/4 round to the subnormal grid), never NaN or negative.
  const GapIntegrals tiny = IntegrateGap(12, den, -den, den);
  EXPECT_NEAR(tiny.below, den, 8 * den);
  EXPECT_NEAR(tiny.above, 5 * den, 8 * den);
}

}  // namespace
}  // namespace surfreg

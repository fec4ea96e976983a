// IntegrateGap, IntegrateGapWeighted and AbsVolumePaper against independent
// truths: values worked out by hand, brute-force quadrature on actual
// triangles in the plane, a separate long-double implementation of the
// split-and-product-rule recipe, and the symmetries of the integrals.
#include "measure/volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "measure/surface.h"

namespace surfreg {
namespace {

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
// Independent reference: the recipe of the design done in long double, by
// explicit geometry in barycentric coordinates. The triangle is cut along the
// zero line of d (cut points interpolated on the edges), the pieces are the
// small triangle at the lone vertex and the quadrilateral split along the
// diagonal from the cut point on the lone-Q edge to P (the other diagonal
// than the one the derivation in volume.cc uses), and the product rule
// ∫fg = A/12 (Σ f_i g_i + Σf Σg) is applied on each piece.
struct RefResult {
  long double abs = 0, above = 0, below = 0, signed_volume = 0, weight = 0;
};

long double ProductRule(long double area, const long double f[3], const long double g[3]) {
  return area / 12 *
         (f[0] * g[0] + f[1] * g[1] + f[2] * g[2] + (f[0] + f[1] + f[2]) * (g[0] + g[1] + g[2]));
}

RefResult Reference(double area_in, const std::array<double, 3>& din,
                    const std::array<double, 3>& min) {
  const long double area = area_in;
  long double d[3], m[3];
  for (int i = 0; i < 3; ++i) d[i] = din[i], m[i] = min[i];
  RefResult r;
  r.signed_volume = ProductRule(area, d, m);
  r.weight = area / 3 * (m[0] + m[1] + m[2]);
  // Lone vertex: strictly of one sign while neither other vertex is.
  int lone = -1;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    if ((d[i] > 0 && d[j] <= 0 && d[k] <= 0 && (d[j] < 0 || d[k] < 0)) ||
        (d[i] < 0 && d[j] >= 0 && d[k] >= 0 && (d[j] > 0 || d[k] > 0))) {
      lone = i;
      break;
    }
  }
  if (lone < 0) {  // one sign (or zero) everywhere: d itself is d⁺ or -d⁻
    const long double absd[3] = {std::fabs(d[0]), std::fabs(d[1]), std::fabs(d[2])};
    const long double v = ProductRule(area, absd, m);
    r.abs = v;
    (d[0] + d[1] + d[2] > 0 ? r.above : r.below) = v;
    return r;
  }
  const int j = (lone + 1) % 3, k = (lone + 2) % 3;
  // X on edge lone-j, Y on edge lone-k, where d vanishes, as barycentric
  // weights (of L and of the other end), each from its own quotient so that
  // neither is a cancelling 1 - t.
  const long double xl = -d[j] / (d[lone] - d[j]), xj = d[lone] / (d[lone] - d[j]);
  const long double yl = -d[k] / (d[lone] - d[k]), yk = d[lone] / (d[lone] - d[k]);
  const long double mx = xl * m[lone] + xj * m[j];
  const long double my = yl * m[lone] + yk * m[k];
  // Areas by barycentric determinants (relative to the triangle): points as
  // barycentric triples (weights of lone, j, k).
  auto area_of = [&](const long double a[3], const long double b[3], const long double c[3]) {
    // With barycentric coordinates, area ratio = |det| of the 3x3 matrix.
    const long double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                            a[2] * (b[0] * c[1] - b[1] * c[0]);
    return area * std::fabs(det);
  };
  const long double L[3] = {1, 0, 0}, P[3] = {0, 1, 0}, Q[3] = {0, 0, 1};
  const long double X[3] = {xl, xj, 0}, Y[3] = {yl, 0, yk};
  const long double small_d[3] = {d[lone], 0, 0}, small_m[3] = {m[lone], mx, my};
  const long double small = ProductRule(area_of(L, X, Y), small_d, small_m);
  // Quadrilateral X P Q Y, split along Y-P: triangles X P Y and Y P Q.
  const long double t1_d[3] = {0, d[j], 0}, t1_m[3] = {mx, m[j], my};
  const long double t2_d[3] = {0, d[j], d[k]}, t2_m[3] = {my, m[j], m[k]};
  const long double quad =
      ProductRule(area_of(X, P, Y), t1_d, t1_m) + ProductRule(area_of(Y, P, Q), t2_d, t2_m);
  const long double small_abs = std::fabs(small), quad_abs = std::fabs(quad);
  r.abs = small_abs + quad_abs;
  r.above = d[lone] > 0 ? small_abs : quad_abs;
  r.below = d[lone] > 0 ? quad_abs : small_abs;
  return r;
}

// ---------------------------------------------------------------------------
// Brute-force quadrature on a triangle with coordinates: the triangle is
// divided into n² congruent subtriangles (the lattice of step 1/n along two
// edges), and each contributes area · integrand(centroid). d and μ are
// evaluated as the planes through (p_i, d_i) and (p_i, m_i) at the centroid's
// (x, y); nothing of measure/volume is used.
//
// Error bound (the tolerance of the tests). The centroid rule is exact for a
// linear integrand on a cell. Per cell C of area A, with d_c, μ_c the
// centroid values (= cell means),
//   ∫_C g(d) μ - A g(d_c) μ_c = μ_c (∫_C g(d) - A g(d_c)) + ∫_C (g(d) - g(d_c))(μ - μ_c)
// for g = |.|, max(., 0), max(-., 0) (g 1-Lipschitz; ∫(μ - μ_c) = 0).
//  * First term: 0 unless d changes sign inside C (g(d) linear there). On a
//    linear d with range r over C, the Jensen gap mean(|d|) - |d_c| is at
//    most 16r/81 < r/5 (maximum at vertex values (2r/3, -r/3, -r/3)), half
//    that for max(±d, 0) (= (|d| ± d)/2). The range on a cell is R_d/n
//    (R_d = max d_i - min d_i) and the zero line, a segment, crosses each of
//    the 3 families of n-1 interior lattice lines at most once, so it meets
//    at most 3n cells: total ≤ 3n · S/n² · M · R_d/(5n) = 0.6 S M R_d / n²
//    (M = max m_i), 0.3 S M R_d / n² for above/below.
//  * Second term: |g(d) - g(d_c)| ≤ |d - d_c| ≤ (2/3) R_d/n and
//    |μ - μ_c| ≤ (2/3) R_μ/n on a cell: total ≤ (4/9) S R_d R_μ / n².
// Without weights (R_μ = 0) the rule also never overestimates: each g is
// convex and the centroid is the cell mean (Jensen).
struct Quadrature {
  long double abs = 0, above = 0, below = 0, signed_volume = 0, weight = 0;
};

struct Plane {
  double x0, y0, f0, gx, gy;
  double operator()(double x, double y) const { return f0 + gx * (x - x0) + gy * (y - y0); }
};

Plane PlaneThrough(const Point2 p[3], const double f[3]) {
  const double e1x = p[1].x - p[0].x, e1y = p[1].y - p[0].y;
  const double e2x = p[2].x - p[0].x, e2y = p[2].y - p[0].y;
  const double det = e1x * e2y - e1y * e2x;
  const double df1 = f[1] - f[0], df2 = f[2] - f[0];
  return {p[0].x, p[0].y, f[0], (df1 * e2y - df2 * e1y) / det, (df2 * e1x - df1 * e2x) / det};
}

double TriangleArea(const Point2 p[3]) {
  return 0.5 * std::fabs((p[1].x - p[0].x) * (p[2].y - p[0].y) -
                         (p[1].y - p[0].y) * (p[2].x - p[0].x));
}

Quadrature Integrate(const Point2 p[3], const double d[3], const double m[3], int n) {
  const Plane pd = PlaneThrough(p, d), pm = PlaneThrough(p, m);
  const double e1x = p[1].x - p[0].x, e1y = p[1].y - p[0].y;
  const double e2x = p[2].x - p[0].x, e2y = p[2].y - p[0].y;
  const long double cell = TriangleArea(p) / (static_cast<double>(n) * n);
  Quadrature q;
  auto add = [&](double u, double v) {  // centroid at p0 + u e1 + v e2
    const double x = p[0].x + u * e1x + v * e2x, y = p[0].y + u * e1y + v * e2y;
    const long double dv = pd(x, y), mv = pm(x, y);
    q.signed_volume += dv * mv;
    q.abs += std::fabs(dv) * mv;
    q.above += std::max(dv, 0.0L) * mv;
    q.below += std::max(-dv, 0.0L) * mv;
    q.weight += mv;
  };
  const double inv = 1.0 / (3.0 * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {
      add((3 * i + 1) * inv, (3 * j + 1) * inv);                      // upright cell
      if (i + j + 2 <= n) add((3 * i + 2) * inv, (3 * j + 2) * inv);  // inverted cell
    }
  }
  q.signed_volume *= cell;
  q.abs *= cell;
  q.above *= cell;
  q.below *= cell;
  q.weight *= cell;
  return q;
}

double Range(const double v[3]) {
  return std::max({v[0], v[1], v[2]}) - std::min({v[0], v[1], v[2]});
}

// A random triangle in [-10, 10]², not too flat (smallest height ≥ 0.1 of
// the longest edge), so that the plane fits above stay well conditioned.
void RandomTriangle(std::mt19937_64& rng, Point2 p[3]) {
  std::uniform_real_distribution<double> u(-10, 10);
  for (;;) {
    for (int i = 0; i < 3; ++i) p[i] = Point2{u(rng), u(rng)};
    double longest = 0;
    for (int i = 0; i < 3; ++i) {
      const Point2 &a = p[i], &b = p[(i + 1) % 3];
      longest = std::max(longest, std::hypot(a.x - b.x, a.y - b.y));
    }
    if (longest > 1 && 2 * TriangleArea(p) / longest >= 0.1 * longest) return;
  }
}

// Values with the sign pattern code (base 3 digits: 0 -> -, 1 -> 0, 2 -> +)
// and magnitudes in [0.05, 1].
std::array<double, 3> PatternValues(std::mt19937_64& rng, int code) {
  std::uniform_real_distribution<double> mag(0.05, 1.0);
  std::array<double, 3> v{};
  for (int i = 0; i < 3; ++i, code /= 3) v[i] = (code % 3 - 1) * mag(rng);
  return v;
}

struct QuadratureStats {
  double worst_fraction_of_bound = 0;  // max over checks of |error| / tolerance
};

// Compares one configuration with quadrature at n; returns the largest
// |error| / tolerance among the five integrals.
double CheckAgainstQuadrature(const Point2 p[3], const std::array<double, 3>& d,
                              const std::array<double, 3>& m, int n, bool weighted) {
  const double area = TriangleArea(p);
  const GapIntegrals g = weighted ? IntegrateGapWeighted(area, d.data(), m.data())
                                  : IntegrateGap(area, d[0], d[1], d[2]);
  const Quadrature q = Integrate(p, d.data(), m.data(), n);
  const double n2 = static_cast<double>(n) * n;
  const double rd = Range(d.data()), rm = Range(m.data());
  const double mmax = std::max({m[0], m[1], m[2]});
  // Rounding: the plane fits and the sums, far below the bound; relative to
  // the natural scale of the integrals.
  const double scale = area * mmax * (std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2]));
  const double round = 1e-12 * scale + 1e-300;
  const double smooth = 4.0 / 9.0 * area * rd * rm / n2;
  const double tol_abs = 0.6 * area * mmax * rd / n2 + smooth + round;
  const double tol_part = 0.3 * area * mmax * rd / n2 + smooth + round;
  const double tol_signed = smooth + round;
  const double tol_weight = round + 1e-12 * area * mmax;
  struct Item {
    const char* name;
    double exact;
    long double quad;
    double tol;
  } items[] = {{"abs", g.abs, q.abs, tol_abs},
               {"above", g.above, q.above, tol_part},
               {"below", g.below, q.below, tol_part},
               {"signed", g.signed_volume, q.signed_volume, tol_signed},
               {"weight", g.weight, q.weight, tol_weight}};
  double worst = 0;
  for (const Item& it : items) {
    const double err = static_cast<double>(it.exact - it.quad);
    EXPECT_LE(std::fabs(err), it.tol)
        << it.name << " n=" << n << " d=(" << d[0] << ", " << d[1] << ", " << d[2] << ") m=("
        << m[0] << ", " << m[1] << ", " << m[2] << ") exact=" << it.exact
        << " quadrature=" << static_cast<double>(it.quad);
    if (!weighted && it.name[0] != 's' && it.name[0] != 'w') {
      // Jensen: the rule underestimates the convex integrands.
      EXPECT_GE(it.exact, static_cast<double>(it.quad) - round) << it.name;
    }
    worst = std::max(worst, std::fabs(err) / it.tol);
  }
  return worst;
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
// Against quadrature.

TEST(VolumeQuadratureTest, EverySignPatternUnweighted) {
  // 27 sign patterns (each vertex -, 0 or +: every choice of lone vertex,
  // both signs, zeros anywhere) x random triangles and magnitudes.
  std::mt19937_64 rng(20240601);
  const std::array<double, 3> one{1, 1, 1};
  double worst = 0;
  for (int code = 0; code < 27; ++code) {
    for (int t = 0; t < 100; ++t) {
      Point2 p[3];
      RandomTriangle(rng, p);
      worst = std::max(worst, CheckAgainstQuadrature(p, PatternValues(rng, code), one, 64, false));
    }
  }
  std::printf("unweighted, n = 64: largest error / tolerance = %.3g\n", worst);
}

TEST(VolumeQuadratureTest, EverySignPatternWeighted) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> weight(0, 2);
  double worst = 0;
  for (int code = 0; code < 27; ++code) {
    for (int t = 0; t < 100; ++t) {
      Point2 p[3];
      RandomTriangle(rng, p);
      std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
      if (t % 4 == 0) m[t / 4 % 3] = 0;  // a weight vanishing at a vertex
      worst = std::max(worst, CheckAgainstQuadrature(p, PatternValues(rng, code), m, 64, true));
    }
  }
  std::printf("weighted, n = 64: largest error / tolerance = %.3g\n", worst);
}

TEST(VolumeQuadratureTest, FineGrid) {
  // n = 400: the bound is 0.6 S M R_d / n² ≈ 3.8e-6 S M R_d, i.e. a few 1e-6
  // relative for values of one scale. Every choice of lone vertex and sign,
  // four times each, with and without weights.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mag(0.1, 1), weight(0, 2);
  double worst = 0;
  for (int trial = 0; trial < 4 * 6; ++trial) {
    const int lone = trial % 3;
    const double sign = trial / 3 % 2 ? -1.0 : 1.0;
    Point2 p[3];
    RandomTriangle(rng, p);
    std::array<double, 3> d{};
    for (int i = 0; i < 3; ++i) d[i] = (i == lone ? sign : -sign) * mag(rng);
    const std::array<double, 3> m{weight(rng), weight(rng), weight(rng)};
    worst = std::max(worst, CheckAgainstQuadrature(p, d, {1, 1, 1}, 400, false));
    worst = std::max(worst, CheckAgainstQuadrature(p, d, m, 400, true));
    // The design's figure, 1e-5 relative at n = 400. With magnitudes in
    // [0.1, 1] the rigorous bound above is at most 2.3e-5 of abs (worst
    // case); the observed error is below a quarter of the bound.
    const GapIntegrals g = IntegrateGap(TriangleArea(p), d[0], d[1], d[2]);
    const std::array<double, 3> one{1, 1, 1};
    const Quadrature q = Integrate(p, d.data(), one.data(), 400);
    EXPECT_NEAR(g.abs, static_cast<double>(q.abs), 1e-5 * g.abs);
  }
  std::printf("n = 400: largest error / tolerance = %.3g\n", worst);
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

#pragma once
// Independent truths and inputs for the measure/volume tests (volume_test.cc
// and volume_quadrature_test.cc): the split-and-product-rule recipe redone
// in long double by explicit geometry, and per-vertex values with a given
// sign pattern. Nothing here calls measure/volume.
#include <array>
#include <cmath>
#include <random>

namespace surfreg::testing {

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

inline long double ProductRule(long double area, const long double f[3], const long double g[3]) {
  return area / 12 *
         (f[0] * g[0] + f[1] * g[1] + f[2] * g[2] + (f[0] + f[1] + f[2]) * (g[0] + g[1] + g[2]));
}

inline RefResult Reference(double area_in, const std::array<double, 3>& din,
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

// Values with the sign pattern code (base 3 digits: 0 -> -, 1 -> 0, 2 -> +)
// and magnitudes in [0.05, 1].
inline std::array<double, 3> PatternValues(std::mt19937_64& rng, int code) {
  std::uniform_real_distribution<double> mag(0.05, 1.0);
  std::array<double, 3> v{};
  for (int i = 0; i < 3; ++i, code /= 3) v[i] = (code % 3 - 1) * mag(rng);
  return v;
}

}  // namespace surfreg::testing

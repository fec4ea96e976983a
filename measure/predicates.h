#pragma once
// Exact geometric predicates on double coordinates. Each is a fast
// floating-point evaluation with a forward error bound (Shewchuk 1997,
// "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates"); when the bound cannot certify the sign, the determinant is
// evaluated exactly with floating-point expansions. The returned value has
// the exact sign of the determinant (its magnitude is approximate).
//
// Domain: any finite coordinates below 2^500 in magnitude, as long as the
// non-zero coordinate differences within one call (and their rounding
// errors, ~2^-53 of the coordinates) span less than 2^480 in magnitude for
// the in-circle test, 2^900 for orientation (e.g. 1e-150 next to 1e0 in one
// in-circle call is outside). The filter hands over to the exact stage
// whenever its products could under- or overflow (differences above 2^240, or
// a determinant scale near the underflow range); the exact stage rescales by
// a power of two that centres the range first, and is exact within these
// spans because every product of the expansion arithmetic is then a normal
// or exactly representable subnormal number.
#include <cmath>

#include "measure/surface.h"

namespace surfreg {

namespace predicates_internal {
constexpr double kEpsilon = 1.1102230246251565e-16;  // 2^-53, half an ulp of 1
// Shewchuk's relative error bounds, widened by 2^-100 to absorb the absolute
// error of products that underflow once the ranges below are enforced.
constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon + 0x1p-100;
constexpr double kInCircleBound = (10.0 + 96.0 * kEpsilon) * kEpsilon + 0x1p-100;
// Outside these ranges the filter does not decide (see the domain above).
constexpr double kOrientMinScale = 0x1p-900;   // |left| + |right|
constexpr double kInCircleMinScale = 0x1p-400;  // permanent
constexpr double kMaxDifference = 0x1p240;      // any coordinate difference
// The exact stages, out of line: reached only when the filter cannot decide.
double Orient2DExact(const Point2& a, const Point2& b, const Point2& c);
int Orient2DCentroidExact(const Point2& a, const Point2& b, const Point2* corners);
double InCircleExact(const Point2& a, const Point2& b, const Point2& c, const Point2& d);
}  // namespace predicates_internal

// > 0 if a, b, c turn counter-clockwise, < 0 clockwise, 0 if collinear.
inline double Orient2D(const Point2& a, const Point2& b, const Point2& c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right;
  const double scale = std::fabs(left) + std::fabs(right);
  const double bound = predicates_internal::kOrientBound * scale;
  // One well-predicted branch (the sign of det is not); the tests also reject
  // NaN from overflowed products.
  if (std::fabs(det) > bound && scale >= predicates_internal::kOrientMinScale) return det;
  return predicates_internal::Orient2DExact(a, b, c);
}

// The signs of Orient2D(t[i + 1], t[i + 2], c) for i = 0, 1, 2 (mod 3), c
// against each edge line of triangle t (edge i opposite corner i), as bits:
// bit i when > 0, bit 3 + i when < 0, neither when c is on the line. Each
// determinant is Orient2D's own floating-point expression (c's differences
// shared) under Orient2D's filter, its exact stage when the filter cannot
// decide: exactly Orient2D's signs, with one branch for the common case.
inline unsigned Orient2DEdgeSignBits(const Point2 t[3], const Point2& c) {
  const double dx[3] = {t[0].x - c.x, t[1].x - c.x, t[2].x - c.x};
  const double dy[3] = {t[0].y - c.y, t[1].y - c.y, t[2].y - c.y};
  constexpr int kNext[3] = {1, 2, 0}, kPrev[3] = {2, 0, 1};
  double det[3];
  bool clear[3];
  for (int i = 0; i < 3; ++i) {
    const double left = dx[kNext[i]] * dy[kPrev[i]];
    const double right = dy[kNext[i]] * dx[kPrev[i]];
    det[i] = left - right;
    const double scale = std::fabs(left) + std::fabs(right);
    // Non-short-circuit: six tests without a branch, then one branch.
    clear[i] = static_cast<bool>((std::fabs(det[i]) > predicates_internal::kOrientBound * scale) &
                                 (scale >= predicates_internal::kOrientMinScale));
  }
  if (clear[0] & clear[1] & clear[2]) {
    // No determinant is zero: the sign bits decide.
    const unsigned negative = static_cast<unsigned>(std::signbit(det[0])) |
                              static_cast<unsigned>(std::signbit(det[1])) << 1 |
                              static_cast<unsigned>(std::signbit(det[2])) << 2;
    return (~negative & 7u) | negative << 3;
  }
  unsigned bits = 0;
  for (int i = 0; i < 3; ++i) {
    if (!clear[i]) det[i] = predicates_internal::Orient2DExact(t[kNext[i]], t[kPrev[i]], c);
    bits |= static_cast<unsigned>(det[i] > 0.0) << i | static_cast<unsigned>(det[i] < 0.0) << (3 + i);
  }
  return bits;
}

// The exact sign of Orient2D(a, b, g) for g = (c[0] + c[1] + c[2]) / 3, the
// centroid of three points, never rounded to a double: +1, -1 or 0 (g on the
// line ab). The determinant is affine in g, so 3 Orient2D(a, b, g) =
// Σ Orient2D(a, b, c[i]), evaluated with the same filter and exact stage as
// Orient2D. Rounding g itself would make the answer depend on the frame the
// points are in when g lies on the line (a centroid on a mesh edge falls on
// either side after a translation by whole units; the union volume's test of
// its triangles against Ω, measure/gap_volume.cc). Same domain as Orient2D.
inline int Orient2DCentroidSign(const Point2& a, const Point2& b, const Point2* c) {
  double det = 0.0, scale = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double left = (a.x - c[i].x) * (b.y - c[i].y);
    const double right = (a.y - c[i].y) * (b.x - c[i].x);
    det += left - right;
    scale += std::fabs(left) + std::fabs(right);
  }
  // Each term's error is Orient2D's bound; the two sums add at most 2 ulps
  // of the scale: (3 + 2) eps, doubled.
  const double bound = 10.0 * predicates_internal::kEpsilon * scale + 0x1p-100 * scale;
  if (std::fabs(det) > bound && scale >= predicates_internal::kOrientMinScale) {
    return det > 0.0 ? 1 : -1;
  }
  return predicates_internal::Orient2DCentroidExact(a, b, c);
}

// The orientation determinant when its floating-point value is already
// accurate to 2^-40 relative (so its sign is exact) in *det, true; false when
// only the exact stage could say. Orient2DAccurate's fast path, inline for
// the hot loops that can use it.
inline bool Orient2DClear(const Point2& a, const Point2& b, const Point2& c, double* det) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  *det = left - right;
  const double scale = std::fabs(left) + std::fabs(right);
  return std::fabs(*det) > 0x1p40 * predicates_internal::kOrientBound * scale &&
         scale >= predicates_internal::kOrientMinScale;
}

// The orientation determinant itself (twice the signed area of a, b, c) with
// the exact sign and a relative error below 2^-40, even for slivers: the
// filter's value when it is that accurate, else the exact expansion's
// leading component. For barycentric coordinates.
inline double Orient2DAccurate(const Point2& a, const Point2& b, const Point2& c) {
  double det;
  return Orient2DClear(a, b, c, &det) ? det : predicates_internal::Orient2DExact(a, b, c);
}

namespace predicates_internal {

// The in-circle determinant's terms in floating point (d's differences,
// their cross products and lifts): one expression for InCircle's filter
// and for any other filter that must see the same det.
struct InCircleTerms {
  double adx, ady, bdx, bdy, cdx, cdy;
  double bdxcdy, cdxbdy, cdxady, adxcdy, adxbdy, bdxady;
  double alift, blift, clift, det;
  // The largest |coordinate difference|.
  double Largest() const {
    const auto larger = [](double p, double q) { return p > q ? p : q; };  // not std::fmax: a call
    return larger(larger(larger(std::fabs(adx), std::fabs(ady)), larger(std::fabs(bdx), std::fabs(bdy))),
                  larger(std::fabs(cdx), std::fabs(cdy)));
  }
};

inline InCircleTerms InCircleTermsOf(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  InCircleTerms t;
  t.adx = a.x - d.x, t.ady = a.y - d.y;
  t.bdx = b.x - d.x, t.bdy = b.y - d.y;
  t.cdx = c.x - d.x, t.cdy = c.y - d.y;
  t.bdxcdy = t.bdx * t.cdy, t.cdxbdy = t.cdx * t.bdy;
  t.cdxady = t.cdx * t.ady, t.adxcdy = t.adx * t.cdy;
  t.adxbdy = t.adx * t.bdy, t.bdxady = t.bdx * t.ady;
  t.alift = t.adx * t.adx + t.ady * t.ady;
  t.blift = t.bdx * t.bdx + t.bdy * t.bdy;
  t.clift = t.cdx * t.cdx + t.cdy * t.cdy;
  t.det = t.alift * (t.bdxcdy - t.cdxbdy) + t.blift * (t.cdxady - t.adxcdy) + t.clift * (t.adxbdy - t.bdxady);
  return t;
}

}  // namespace predicates_internal

// > 0 if d lies inside the circle through a, b, c (given counter-clockwise),
// < 0 outside, 0 on it. Sign flips if a, b, c are clockwise.
inline double InCircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const predicates_internal::InCircleTerms t = predicates_internal::InCircleTermsOf(a, b, c, d);
  const double permanent = (std::fabs(t.bdxcdy) + std::fabs(t.cdxbdy)) * t.alift +
                           (std::fabs(t.cdxady) + std::fabs(t.adxcdy)) * t.blift +
                           (std::fabs(t.adxbdy) + std::fabs(t.bdxady)) * t.clift;
  const double bound = predicates_internal::kInCircleBound * permanent;
  // A NaN difference already makes det NaN, which fails the first test.
  if (std::fabs(t.det) > bound && permanent >= predicates_internal::kInCircleMinScale &&
      t.Largest() <= predicates_internal::kMaxDifference) {
    return t.det;
  }
  return predicates_internal::InCircleExact(a, b, c, d);
}

// In-circle with symbolic perturbation: never 0 for four distinct points
// with a, b, c not collinear. Ties (d exactly on the circle) are broken as
// if each point's lifted height x² + y² were raised by an infinitesimal that
// is larger for lexicographically larger (x, then y) points. The tie-break
// depends only on coordinates, so the Delaunay triangulation it defines is
// unique and independent of input order (e.g. the diagonal chosen in each
// cell of a grid). Returns +1 (inside) or -1 (outside).
int InCirclePerturbedTie(const Point2& a, const Point2& b, const Point2& c, const Point2& d);
inline int InCirclePerturbed(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double det = InCircle(a, b, c, d);
  if (det > 0.0) return 1;
  if (det < 0.0) return -1;
  return InCirclePerturbedTie(a, b, c, d);
}

// Counters of how often the exact stage ran (for tests and benchmarks).
struct PredicateCounters {
  unsigned long long orient_exact = 0;
  unsigned long long incircle_exact = 0;
  unsigned long long incircle_ties = 0;
};
PredicateCounters& ThreadPredicateCounters();

}  // namespace surfreg

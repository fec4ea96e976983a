#include "measure/predicates.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace surfreg {
namespace {

// Floating-point expansions: a value represented exactly as a sum of
// doubles with non-overlapping bits, stored from least to most significant.
// Only the sign of the final sum matters, which is the sign of its most
// significant non-zero component.

// a + b = sum + err exactly.
inline void TwoSum(double a, double b, double& sum, double& err) {
  sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  err = (a - a_virtual) + (b - b_virtual);
}

// a * b = product + err exactly (fused multiply-add gives the rounding error).
inline void TwoProduct(double a, double b, double& product, double& err) {
  product = a * b;
  err = std::fma(a, b, -product);
}

// h = e + f, both expansions; zero components dropped. Returns length of h.
// h must not alias e or f and must have room for ne + nf components.
int ExpansionSum(int ne, const double* e, int nf, const double* f, double* h) {
  // Merge by magnitude, then accumulate with TwoSum (linear expansion sum).
  int i = 0, j = 0, nh = 0;
  double q = 0.0;
  bool have_q = false;
  while (i < ne || j < nf) {
    double next;
    if (j >= nf || (i < ne && std::fabs(e[i]) < std::fabs(f[j]))) {
      next = e[i++];
    } else {
      next = f[j++];
    }
    if (!have_q) {
      q = next;
      have_q = true;
      continue;
    }
    double sum, err;
    TwoSum(q, next, sum, err);
    if (err != 0.0) h[nh++] = err;
    q = sum;
  }
  if (have_q && (q != 0.0 || nh == 0)) h[nh++] = q;
  return nh;
}

// h = b * e exactly; zero components dropped. h needs room for 2 * ne.
int ScaleExpansion(int ne, const double* e, double b, double* h) {
  int nh = 0;
  double q, err;
  TwoProduct(e[0], b, q, err);
  if (err != 0.0) h[nh++] = err;
  for (int i = 1; i < ne; ++i) {
    double p1, p0;
    TwoProduct(e[i], b, p1, p0);
    double s, e1;
    TwoSum(q, p0, s, e1);
    if (e1 != 0.0) h[nh++] = e1;
    double s2, e2;
    TwoSum(p1, s, s2, e2);
    if (e2 != 0.0) h[nh++] = e2;
    q = s2;
  }
  if (q != 0.0 || nh == 0) h[nh++] = q;
  return nh;
}

// h = e * f exactly. h needs room for 2 * ne * nf; scratch for the same.
int ExpansionProduct(int ne, const double* e, int nf, const double* f, double* h,
                     double* scratch) {
  double term[64];
  int nh = 0;
  for (int j = 0; j < nf; ++j) {
    const int nt = ScaleExpansion(ne, e, f[j], term);
    const int n = ExpansionSum(nh, h, nt, term, scratch);
    for (int k = 0; k < n; ++k) h[k] = scratch[k];
    nh = n;
  }
  return nh;
}

double MostSignificant(int n, const double* e) { return e[n - 1]; }

// a - b as an exact two-component expansion; returns its length (1 or 2).
int ExactDifference(double a, double b, double* h) {
  double d, err;
  TwoSum(a, -b, d, err);
  if (err == 0.0) {
    h[0] = d;
    return 1;
  }
  h[0] = err;
  h[1] = d;
  return 2;
}

// Scales the expansions arrays[k] (lengths[k] components each) by one power
// of two that brings the largest component to [2^(target-1), 2^target). The
// predicates' determinants are homogeneous, so their signs are unchanged.
// Centring the range (target 500 for degree 2, 240 for degree 4) keeps the
// largest products below overflow and leaves the most room for the smallest
// components' products above underflow (see the domain in predicates.h).
// Returns the exponent e of the scaling 2^-e applied.
int ScaleToRange(double* const* arrays, const int* lengths, int count, int target) {
  double largest = 0.0;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < lengths[k]; ++i) largest = std::max(largest, std::fabs(arrays[k][i]));
  }
  if (largest == 0.0) return 0;
  int exponent;
  std::frexp(largest, &exponent);
  exponent -= target;
  if (exponent == 0) return 0;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < lengths[k]; ++i) arrays[k][i] = std::ldexp(arrays[k][i], -exponent);
  }
  return exponent;
}

// value * 2^exponent, never rounded to zero (the sign is what matters).
double Unscale(double value, int exponent) {
  const double result = std::ldexp(value, exponent);
  if (result == 0.0 && value != 0.0) {
    return std::copysign(std::numeric_limits<double>::denorm_min(), value);
  }
  return result;
}

}  // namespace

namespace predicates_internal {

double Orient2DExact(const Point2& a, const Point2& b, const Point2& c) {
  ++ThreadPredicateCounters().orient_exact;
  // Shift by c exactly (two-component differences), then the 2x2 determinant.
  double acx[2], acy[2], bcx[2], bcy[2];
  const int nacx = ExactDifference(a.x, c.x, acx);
  const int nacy = ExactDifference(a.y, c.y, acy);
  const int nbcx = ExactDifference(b.x, c.x, bcx);
  const int nbcy = ExactDifference(b.y, c.y, bcy);
  double* const arrays[4] = {acx, acy, bcx, bcy};
  const int lengths[4] = {nacx, nacy, nbcx, nbcy};
  const int exponent = ScaleToRange(arrays, lengths, 4, 500);  // determinant scales by 2^-2e
  if (nacx == 1 && nacy == 1 && nbcx == 1 && nbcy == 1) {
    // Exact differences (grids): rounding is monotone, so unequal rounded
    // products order the exact ones; equal ones leave the exact errors.
    double left, left_err, right, right_err;
    TwoProduct(acx[0], bcy[0], left, left_err);
    TwoProduct(acy[0], bcx[0], right, right_err);
    if (left == right) return Unscale(left_err - right_err, 2 * exponent);
    // Keep a magnitude too, with the sign that left > right decides.
    double value = (left - right) + (left_err - right_err);
    if ((value > 0.0) != (left > right)) {
      value = left > right ? std::numeric_limits<double>::min()
                           : -std::numeric_limits<double>::min();
    }
    return Unscale(value, 2 * exponent);
  }
  double left[8], right[8], scratch[8], det[16];
  const int nl = ExpansionProduct(nacx, acx, nbcy, bcy, left, scratch);
  const int nr = ExpansionProduct(nacy, acy, nbcx, bcx, right, scratch);
  for (int k = 0; k < nr; ++k) right[k] = -right[k];
  const int nd = ExpansionSum(nl, left, nr, right, det);
  return Unscale(MostSignificant(nd, det), 2 * exponent);
}

}  // namespace predicates_internal

namespace {

// 2x2 minor p.x * q.y - p.y * q.x of exact difference expansions.
int Minor(int npx, const double* px, int npy, const double* py, int nqx, const double* qx, int nqy,
          const double* qy, double* h) {
  double l[8], r[8], scratch[8];
  const int nl = ExpansionProduct(npx, px, nqy, qy, l, scratch);
  const int nr = ExpansionProduct(npy, py, nqx, qx, r, scratch);
  for (int k = 0; k < nr; ++k) r[k] = -r[k];
  return ExpansionSum(nl, l, nr, r, h);
}

// Exact in-circle when the six coordinate differences are exact doubles that
// become integers below 2^28 after one common power-of-two scaling (grids,
// data on a lattice: the ties that reach the exact stage). Then every term
// fits a 128-bit integer: lifts and minors < 2^57, products < 2^114.
// Returns false if the shortcut does not apply.
__extension__ typedef __int128 int128;  // GCC and Clang on 64-bit targets

bool InCircleLattice(const double d[6], double* sign) {
  double largest = 0.0;
  for (int k = 0; k < 6; ++k) largest = std::max(largest, std::fabs(d[k]));
  if (largest == 0.0) {
    *sign = 0.0;
    return true;
  }
  int exponent;
  std::frexp(largest, &exponent);  // largest < 2^exponent
  int128 v[6];
  for (int k = 0; k < 6; ++k) {
    const double scaled = std::ldexp(d[k], 28 - exponent);  // |scaled| < 2^28, exact
    if (scaled != std::nearbyint(scaled)) return false;
    v[k] = static_cast<int128>(scaled);
  }
  const int128 alift = v[0] * v[0] + v[1] * v[1];
  const int128 blift = v[2] * v[2] + v[3] * v[3];
  const int128 clift = v[4] * v[4] + v[5] * v[5];
  const int128 det = alift * (v[2] * v[5] - v[4] * v[3]) +
                       blift * (v[4] * v[1] - v[0] * v[5]) +
                       clift * (v[0] * v[3] - v[2] * v[1]);
  *sign = det > 0 ? 1.0 : (det < 0 ? -1.0 : 0.0);
  return true;
}

}  // namespace

namespace predicates_internal {

double InCircleExact(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  ++ThreadPredicateCounters().incircle_exact;
  {
    double diff[6], err[6];
    TwoSum(a.x, -d.x, diff[0], err[0]);
    TwoSum(a.y, -d.y, diff[1], err[1]);
    TwoSum(b.x, -d.x, diff[2], err[2]);
    TwoSum(b.y, -d.y, diff[3], err[3]);
    TwoSum(c.x, -d.x, diff[4], err[4]);
    TwoSum(c.y, -d.y, diff[5], err[5]);
    double sign;
    if (err[0] == 0.0 && err[1] == 0.0 && err[2] == 0.0 && err[3] == 0.0 && err[4] == 0.0 &&
        err[5] == 0.0 && InCircleLattice(diff, &sign)) {
      return sign;
    }
  }
  double ax[2], ay[2], bx[2], by[2], cx[2], cy[2];
  const int nax = ExactDifference(a.x, d.x, ax), nay = ExactDifference(a.y, d.y, ay);
  const int nbx = ExactDifference(b.x, d.x, bx), nby = ExactDifference(b.y, d.y, by);
  const int ncx = ExactDifference(c.x, d.x, cx), ncy = ExactDifference(c.y, d.y, cy);
  {
    double* const arrays[6] = {ax, ay, bx, by, cx, cy};
    const int lengths[6] = {nax, nay, nbx, nby, ncx, ncy};
    ScaleToRange(arrays, lengths, 6, 240);  // only the sign is returned: no need to undo
  }

  double bc[16], ca[16], ab[16];
  const int nbc = Minor(nbx, bx, nby, by, ncx, cx, ncy, cy, bc);
  const int nca = Minor(ncx, cx, ncy, cy, nax, ax, nay, ay, ca);
  const int nab = Minor(nax, ax, nay, ay, nbx, bx, nby, by, ab);

  // lift(p) = px^2 + py^2 as an expansion (up to 16 components).
  auto lift = [](int nx, const double* x, int ny, const double* y, double* h) {
    double xx[8], yy[8], scratch[8];
    const int nxx = ExpansionProduct(nx, x, nx, x, xx, scratch);
    const int nyy = ExpansionProduct(ny, y, ny, y, yy, scratch);
    return ExpansionSum(nxx, xx, nyy, yy, h);
  };
  double la[16], lb[16], lc[16];
  const int nla = lift(nax, ax, nay, ay, la);
  const int nlb = lift(nbx, bx, nby, by, lb);
  const int nlc = lift(ncx, cx, ncy, cy, lc);

  // det = la * bc + lb * ca + lc * ab; each product has at most 2*16*16 terms.
  static thread_local double ta[512], tb[512], tc[512], scratch[512], sum1[1024], det[1536];
  const int nta = ExpansionProduct(nla, la, nbc, bc, ta, scratch);
  const int ntb = ExpansionProduct(nlb, lb, nca, ca, tb, scratch);
  const int ntc = ExpansionProduct(nlc, lc, nab, ab, tc, scratch);
  const int ns = ExpansionSum(nta, ta, ntb, tb, sum1);
  const int nd = ExpansionSum(ns, sum1, ntc, tc, det);
  return MostSignificant(nd, det);
}

int Orient2DCentroidExact(const Point2& a, const Point2& b, const Point2* c) {
  ++ThreadPredicateCounters().orient_exact;
  // Σ_i (a − c_i) × (b − c_i) with every difference an exact expansion and
  // one common power-of-two scaling (the sum is homogeneous of degree 2).
  double d[12][2];
  int n[12];
  for (int i = 0; i < 3; ++i) {
    n[4 * i + 0] = ExactDifference(a.x, c[i].x, d[4 * i + 0]);
    n[4 * i + 1] = ExactDifference(a.y, c[i].y, d[4 * i + 1]);
    n[4 * i + 2] = ExactDifference(b.x, c[i].x, d[4 * i + 2]);
    n[4 * i + 3] = ExactDifference(b.y, c[i].y, d[4 * i + 3]);
  }
  double* arrays[12];
  for (int k = 0; k < 12; ++k) arrays[k] = d[k];
  ScaleToRange(arrays, n, 12, 500);  // products < 2^1000, their sum of six < 2^1003
  double sum[48], next[48];
  int ns = 0;
  for (int i = 0; i < 3; ++i) {
    double* const acx = d[4 * i + 0];
    double* const acy = d[4 * i + 1];
    double* const bcx = d[4 * i + 2];
    double* const bcy = d[4 * i + 3];
    double det[16];
    const int nd = Minor(n[4 * i + 0], acx, n[4 * i + 1], acy, n[4 * i + 2], bcx, n[4 * i + 3],
                         bcy, det);
    const int nn = ExpansionSum(ns, sum, nd, det, next);
    std::copy(next, next + nn, sum);
    ns = nn;
  }
  const double most = MostSignificant(ns, sum);
  return most > 0.0 ? 1 : (most < 0.0 ? -1 : 0);
}

}  // namespace predicates_internal

PredicateCounters& ThreadPredicateCounters() {
  static thread_local PredicateCounters counters;
  return counters;
}

namespace {

bool LexLess(const Point2& p, const Point2& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); }

}  // namespace

int InCirclePerturbedTie(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  ++ThreadPredicateCounters().incircle_ties;
  // The in-circle determinant is det[x y (x²+y²) 1] over rows a, b, c, d.
  // Raising row r's lifted height by δ_r adds δ_r times its cofactor:
  //   a: +orient(b,c,d)  b: -orient(a,c,d)  c: +orient(a,b,d)  d: -orient(a,b,c).
  // The lexicographically largest point has the dominant δ, so the first
  // non-zero cofactor in that order decides.
  const Point2* p[4] = {&a, &b, &c, &d};
  int order[4] = {0, 1, 2, 3};
  for (int i = 1; i < 4; ++i) {  // insertion sort, largest first
    for (int j = i; j > 0 && LexLess(*p[order[j - 1]], *p[order[j]]); --j) {
      std::swap(order[j - 1], order[j]);
    }
  }
  for (int k = 0; k < 4; ++k) {
    double cofactor = 0.0;
    switch (order[k]) {
      case 0: cofactor = Orient2D(b, c, d); break;
      case 1: cofactor = -Orient2D(a, c, d); break;
      case 2: cofactor = Orient2D(a, b, d); break;
      case 3: cofactor = -Orient2D(a, b, c); break;
    }
    if (cofactor > 0.0) return 1;
    if (cofactor < 0.0) return -1;
  }
  return -1;  // only for degenerate (collinear or repeated) input; callers avoid it
}

}  // namespace surfreg

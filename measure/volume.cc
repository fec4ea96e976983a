#include "measure/volume.h"

// Derivation.
//
// Product rule: for f, g linear on a triangle T of area A with vertex values
// f_i, g_i,  ∫_T f g = A/12 · (Σ f_i g_i + Σ f_i · Σ g_i)  (g = 1: A/3·Σ f_i).
//
// No sign change (all values ≥ 0 or all ≤ 0): d⁺ or d⁻ is d or -d on the
// whole triangle, so the product rule applies directly.
//
// Sign change: let L be the lone vertex (the one whose strict sign the other
// two, P and Q, do not share; a zero among P, Q is allowed) and write the
// values as magnitudes: d_L = s·l, d_P = -s·p, d_Q = -s·q with l > 0,
// p, q ≥ 0, s = ±1. d vanishes at
//   X = L + t1 (P - L),  t1 = l/(l+p),    Y = L + t2 (Q - L),  t2 = l/(l+q),
// and we also use the complements α = p/(l+p) = 1 - t1, β = q/(l+q) = 1 - t2,
// each evaluated by its own division (never as 1 - t). All of t1, t2, α, β
// lie in [0, 1] and l > 0, so no division by zero and no overflow.
// Pieces (areas from shared heights: X splits LP at t1, Y splits LQ at t2):
//   small triangle  L X Y : area S t1 t2,    d = s·(l, 0, 0)
//   triangle        X P Q : area S α,        d = -s·(0, p, q)
//   triangle        X Q Y : area S t1 β,     d = -s·(0, q, 0)
// (S t1 t2 + S α + S t1 β = S.) Unweighted, each piece is A/3·Σd:
//   lone side  = S/3 · l t1 t2                      (= S l³/(3(l+p)(l+q)))
//   other side = S/3 · (p α + q t1 β + q α)
//              = S/3 · (p α + q β + l α β),
// since q t1 β + q α = q β + q α (1 - β) = q β + q α t2 = q β + l α β
// (q t2 = l β); both equal S/3·[l(p²+pq+q²) + pq(p+q)]/((l+p)(l+q)).
// The symmetric last form has only non-negative terms: no cancellation,
// unlike "total minus small triangle", and it is symmetric in P <-> Q.
// Check (1, -1, 1), S = 1: below = 1/12, above = 5/12, abs = 1/2.
//
// Weighted: μ at the cut points is μ_X = α m_L + t1 m_P, μ_Y = β m_L + t2 m_Q.
// Small triangle by the product rule:
//   S t1 t2 · l/12 · ((2 + α + β) m_L + t1 m_P + t2 m_Q).
// Quadrilateral (the two triangles above, summed and regrouped per vertex
// weight so that the result is symmetric in P <-> Q; checked symbolically
// against "total minus small triangle"):  S/12 · (c_L m_L + c_P m_P + c_Q m_Q),
//   c_L = (1 - t1 t2)(p α + q β),  1 - t1 t2 = α β + α t2 + t1 β,
//   c_P = α (2p + q + t1 (p + q)) + t1² β q,
//   c_Q = β (2q + p + t2 (q + p)) + t2² α p.
// With μ = 1, c_L + c_P + c_Q = 4 (p α + q β + l α β), the unweighted form.
// Every term is a product of non-negative factors (given m ≥ 0).
//
// One vertex value exactly 0 (Z) and the others of opposite signs (U > 0,
// W < 0, magnitudes u, w): the zero line is the segment from Z to
// C = U + tu (W - U), tu = u/(u+w), tw = w/(u+w); the pieces (U, C, Z) and
// (W, C, Z) have areas S tu and S tw, so above = S/3 · u tu, below =
// S/3 · w tw, and with μ (μ_C = tw m_U + tu m_W):
//   above = S/12 · u tu (2 m_U + μ_C + m_Z),  below likewise with W.
// This is the lone-vertex split with q = 0 (either non-zero vertex as L),
// written so that U and W are treated alike.
//
// The signed integral and the weight come from their own definitions, with
// the three-term sums taken in a canonical (sorted) order so that permuting
// the vertices changes no result and negating d negates the signed integral
// exactly.

namespace surfreg {
namespace {

inline double Min(double x, double y) { return y < x ? y : x; }
inline double Max(double x, double y) { return x < y ? y : x; }
inline double Abs(double x) { return x < 0 ? -x : x; }

// x + y + z in an order that depends only on the multiset {x, y, z}, and
// with Sum3(-x, -y, -z) == -Sum3(x, y, z) exactly: (min + max) + median.
inline double Sum3(double x, double y, double z) {
  const double lo = Min(Min(x, y), z);
  const double hi = Max(Max(x, y), z);
  const double mid = Max(Min(x, y), Min(Max(x, y), z));
  return (lo + hi) + mid;
}

// The sign-change configuration: lone vertex index and magnitudes.
struct Split {
  int lone;     // index of L; P = lone + 1, Q = lone + 2 (mod 3)
  double sign;  // s: sign of d at L
  double l, p, q;
  double t1, t2, alpha, beta;
};

constexpr int kNext[3] = {1, 2, 0};
constexpr int kPrev[3] = {2, 0, 1};

// Requires a strict sign change (some value > 0 and some < 0). The lone
// vertex is the only positive one if there is exactly one, else the only
// negative one.
inline Split MakeSplit(const double v[3], int positives) {
  Split s;
  s.sign = positives == 1 ? 1.0 : -1.0;
  s.lone = s.sign * v[0] > 0 ? 0 : (s.sign * v[1] > 0 ? 1 : 2);
  s.l = s.sign * v[s.lone];
  s.p = -s.sign * v[kNext[s.lone]];
  s.q = -s.sign * v[kPrev[s.lone]];
  const double lp = s.l + s.p, lq = s.l + s.q;
  s.t1 = s.l / lp;
  s.alpha = s.p / lp;
  s.t2 = s.l / lq;
  s.beta = s.q / lq;
  return s;
}

// One value exactly 0, the other two of opposite signs: the zero line runs
// from the zero vertex Z to the cut point C on the opposite edge, splitting
// the triangle into (U, C, Z) with d⁺ and (W, C, Z) with d⁻, of areas S·tu
// and S·tw. (The lone-vertex split gives the same with either non-zero
// vertex as L; this form treats both alike, so negating d swaps above and
// below exactly.)
struct Zero {
  int pos, neg;  // indices of the positive and the negative vertex
  double u, w;   // their magnitudes
  double tu, tw;  // u/(u+w), w/(u+w): C = U + tu (W - U)
};

inline Zero MakeZero(const double v[3]) {
  Zero z;
  z.pos = v[0] > 0 ? 0 : (v[1] > 0 ? 1 : 2);
  z.neg = v[0] < 0 ? 0 : (v[1] < 0 ? 1 : 2);
  z.u = v[z.pos];
  z.w = -v[z.neg];
  const double uw = z.u + z.w;
  z.tu = z.u / uw;
  z.tw = z.w / uw;
  return z;
}

}  // namespace

GapIntegrals IntegrateGap(double area, double a, double b, double c) {
  GapIntegrals r;
  const double k = area / 3;
  r.weight = area;
  r.signed_volume = k * Sum3(a, b, c);
  const int positives = (a > 0) + (b > 0) + (c > 0);
  const int negatives = (a < 0) + (b < 0) + (c < 0);
  if (positives == 0 || negatives == 0) {
    const double v = k * Sum3(Abs(a), Abs(b), Abs(c));
    r.abs = v;
    (positives > 0 ? r.above : r.below) = v;
    return r;
  }
  const double vals[3] = {a, b, c};
  if (positives + negatives == 2) {
    const Zero z = MakeZero(vals);
    r.above = k * (z.u * z.tu);
    r.below = k * (z.w * z.tw);
    r.abs = r.above + r.below;
    return r;
  }
  const Split s = MakeSplit(vals, positives);
  const double lone = k * (s.l * (s.t1 * s.t2));
  const double other = k * ((s.p * s.alpha + s.q * s.beta) + s.l * (s.alpha * s.beta));
  r.abs = lone + other;
  r.above = s.sign > 0 ? lone : other;
  r.below = s.sign > 0 ? other : lone;
  return r;
}

GapIntegrals IntegrateGapWeighted(double area, const double d[3], const double m[3]) {
  GapIntegrals r;
  const double k = area / 12;
  const double msum = Sum3(m[0], m[1], m[2]);
  r.weight = (area / 3) * msum;
  r.signed_volume = k * (Sum3(d[0] * m[0], d[1] * m[1], d[2] * m[2]) + Sum3(d[0], d[1], d[2]) * msum);
  const int positives = (d[0] > 0) + (d[1] > 0) + (d[2] > 0);
  const int negatives = (d[0] < 0) + (d[1] < 0) + (d[2] < 0);
  if (positives == 0 || negatives == 0) {
    const double a0 = Abs(d[0]), a1 = Abs(d[1]), a2 = Abs(d[2]);
    const double v = k * (Sum3(a0 * m[0], a1 * m[1], a2 * m[2]) + Sum3(a0, a1, a2) * msum);
    r.abs = v;
    (positives > 0 ? r.above : r.below) = v;
    return r;
  }
  if (positives + negatives == 2) {
    const Zero z = MakeZero(d);
    const double mu = m[z.pos], mw = m[z.neg], mz = m[3 - z.pos - z.neg];
    const double mc = z.tw * mu + z.tu * mw;  // μ at the cut point
    r.above = k * ((z.u * z.tu) * ((2 * mu + mz) + mc));
    r.below = k * ((z.w * z.tw) * ((2 * mw + mz) + mc));
    r.abs = r.above + r.below;
    return r;
  }
  const Split s = MakeSplit(d, positives);
  const double mL = m[s.lone], mP = m[kNext[s.lone]], mQ = m[kPrev[s.lone]];
  const double lone =
      k * ((s.l * (s.t1 * s.t2)) *
           ((2 + (s.alpha + s.beta)) * mL + (s.t1 * mP + s.t2 * mQ)));
  const double cL = (s.alpha * s.beta + (s.alpha * s.t2 + s.t1 * s.beta)) *
                    (s.p * s.alpha + s.q * s.beta);
  const double cP = s.alpha * ((2 * s.p + s.q) + s.t1 * (s.p + s.q)) +
                    (s.t1 * s.t1) * (s.beta * s.q);
  const double cQ = s.beta * ((2 * s.q + s.p) + s.t2 * (s.q + s.p)) +
                    (s.t2 * s.t2) * (s.alpha * s.p);
  const double other = k * (cL * mL + (cP * mP + cQ * mQ));
  r.abs = lone + other;
  r.above = s.sign > 0 ? lone : other;
  r.below = s.sign > 0 ? other : lone;
  return r;
}

double AbsVolumePaper(double area, double a, double b, double c) {
  const int positives = (a > 0) + (b > 0) + (c > 0);
  const int negatives = (a < 0) + (b < 0) + (c < 0);
  if (positives == 0 || negatives == 0) {
    return area * (Abs(a) + Abs(b) + Abs(c)) / 3;
  }
  // The lone vertex plays the paper's b; s is the sign of the other two.
  const double vals[3] = {a, b, c};
  const double lone_sign = positives == 1 ? 1.0 : -1.0;
  const int i = lone_sign * a > 0 ? 0 : (lone_sign * b > 0 ? 1 : 2);
  const double bb = Abs(vals[i]);
  const double aa = Abs(vals[kNext[i]]), cc = Abs(vals[kPrev[i]]);
  const double s = -lone_sign;
  return s * area * (a + b + c) / 3 + 2 * area / 3 * bb * (bb / (bb + aa)) * (bb / (bb + cc));
}

}  // namespace surfreg

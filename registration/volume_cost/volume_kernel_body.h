#pragma once
// Internal to volume_kernel_avx512.cc and volume_kernel_avx2.cc only: the
// vector cell kernel of volume_kernel_simd.h, written once over a lane type
// V that each of those files defines for its instruction set.
//
// Those files are compiled for AVX-512 / AVX2, so every function they emit
// out of line may use those instructions. One with external linkage (an
// inline function of a shared header, a template instantiated on shared
// types) could be merged by the linker with a baseline copy from another
// file and then run on a CPU without them. Hence: everything here is in an
// anonymous namespace and templated on V (itself in the includer's
// anonymous namespace), and calls no inline function of another header (the
// input is plain arrays and structs); intrinsics and builtins are never
// emitted out of line.
//
// V has, all static (D: kLanes doubles, with the vector extensions' + − × ÷;
// M: a lane mask; I: kLanes 64-bit integers):
//   kLanes; Set(c), Zero(), Load(p), Store(p, x) (aligned); Min, Max;
//   FmAdd(a, b, c) = ab + c, FnmAdd(a, b, c) = c − ab, each one rounding;
//   Gt, Lt, Neq → M; And, Or, Xor, AndNot(a, b) = ¬a ∧ b on masks;
//   Blend(m, a, b) = m ? b : a; MaskZ(m, a) = m ? a : 0;
//   MaskDiv(src, m, a, b) = m ? a/b : src (other lanes may divide by 0);
//   FirstLanes(n) → M; Bits(m): bit l for lane l; ReduceAdd(x) → double;
//   LoadInt(p) (aligned), Shift8(x) = x >> 8, TestBit<b>(x) → M;
//   LoadRecords(base, index, out[8]): field f of base[index[l]] → out[f][l];
//   LoadExtras(base, index, &z0, &bits): z0 and the 64-bit word at `bits`.
#include <cstdint>

#include "registration/volume_cost/volume_kernel_simd.h"

namespace surfreg {
namespace volume_internal {
namespace {

// Up to kLanes cells, one per lane. Corner codes are padded past
// num_corners with the last corner: a repeated corner makes zero-area fan
// triangles (exactly: no FP contraction, -ffp-contract=off from
// surfreg_measure), which add nothing.
template <class V>
struct Batch {
  static constexpr int kLanes = V::kLanes;
  alignas(64) int32_t ta[kLanes];
  alignas(64) int32_t tb[kLanes];
  alignas(64) uint64_t code[kLanes];
  alignas(64) double za0[kLanes];       // T_A's extras, copied per A triangle
  alignas(64) uint64_t bits_a[kLanes];
  alignas(64) double mu0[kLanes], mu_gx[kLanes], mu_gy[kLanes];  // T_A's μ plane (weighted)
  uint8_t n[kLanes];
  int size = 0;
  int max_n = 0;
};

// Per-lane accumulators of one batch of cells.
template <class V>
struct CellSums {
  typename V::D abs, w, mx, my, twice;
  typename V::D mu;  // ∫μ (weighted only)
};

template <class V>
inline typename V::D Select3(typename V::M is1, typename V::M is2, typename V::D v0,
                             typename V::D v1, typename V::D v2) {
  return V::Blend(is2, V::Blend(is1, v0, v1), v2);
}

// Where d = 0 cuts a fan triangle (d0, d1, d2), branch-free: the corner L
// whose sign is alone (the positive one if alone, else the negative one;
// l1/l2 select corner 1/2, (L, J, K) keeps the orientation), a = d_L/(d_L −
// d_J), b = d_L/(d_L − d_K) (zero where d has one sign), f = a·b the area
// fraction of the part (L, L + a(J − L), L + b(K − L)) cut off, and s the
// sign of the rest.
template <class V>
struct LoneSign {
  typename V::M l1, l2;
  typename V::D dl, a, b, f, s;
};

template <class V>
inline LoneSign<V> SplitOf(typename V::D d0, typename V::D d1, typename V::D d2) {
  using D = typename V::D;
  using M = typename V::M;
  const D zero = V::Zero();
  const M p0 = V::Gt(d0, zero), p1 = V::Gt(d1, zero), p2 = V::Gt(d2, zero);
  const M n0 = V::Lt(d0, zero), n1 = V::Lt(d1, zero), n2 = V::Lt(d2, zero);
  const M any_pos = V::Or(V::Or(p0, p1), p2), any_neg = V::Or(V::Or(n0, n1), n2);
  const M split = V::And(any_pos, any_neg);
  const M one_pos = V::AndNot(V::And(V::And(p0, p1), p2), V::Xor(V::Xor(p0, p1), p2));
  LoneSign<V> r;
  r.l1 = V::Or(V::And(one_pos, p1), V::AndNot(one_pos, n1));
  r.l2 = V::Or(V::And(one_pos, p2), V::AndNot(one_pos, n2));
  r.dl = Select3<V>(r.l1, r.l2, d0, d1, d2);
  const D dj = Select3<V>(r.l1, r.l2, d1, d2, d0);
  const D dk = Select3<V>(r.l1, r.l2, d2, d0, d1);
  // Split lanes only: there d_L − d_J, d_L − d_K ≠ 0 (opposite signs or
  // zero). One division for both.
  const D lj = r.dl - dj, lk = r.dl - dk;
  const D q = V::MaskDiv(zero, split, r.dl, lj * lk);
  r.a = q * lk;
  r.b = q * lj;
  r.f = r.a * r.b;
  const M s_pos = V::Or(V::AndNot(split, any_pos), V::AndNot(one_pos, split));
  const M s_neg = V::Or(V::AndNot(split, any_neg), V::And(split, one_pos));
  r.s = V::Blend(s_pos, V::MaskZ(s_neg, V::Set(-1.0)), V::Set(1.0));
  return r;
}

template <class V>
inline typename V::D TwiceAreaOf(typename V::D x0, typename V::D y0, typename V::D x1,
                                 typename V::D y1, typename V::D x2, typename V::D y2) {
  return (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
}

// One fan triangle (p0, p1, p2) with d linear on it: the whole triangle's
// ∫d, area and first moment, minus twice those of the part cut off by d = 0
// (SplitOf), times s: ∫|d|, and the signed area and moment.
template <class V, bool kGradient>
inline void Fan(typename V::D x0, typename V::D y0, typename V::D d0, typename V::D x1,
                typename V::D y1, typename V::D d1, typename V::D x2, typename V::D y2,
                typename V::D d2, CellSums<V>* c) {
  using D = typename V::D;
  const D t = TwiceAreaOf<V>(x0, y0, x1, y1, x2, y2);
  c->twice = c->twice + t;
  const D h = t * V::Set(1.0 / 6.0);
  const D sd = (d0 + d1) + d2;
  const LoneSign<V> z = SplitOf<V>(d0, d1, d2);
  const D sh = z.s * h;
  const D two_f = z.f + z.f;
  // s h (Σd − 2 f d_L) = s (∫d − 2 ∫_sub d)
  c->abs = V::FmAdd(sh, V::FnmAdd(two_f, z.dl, sd), c->abs);
  if (!kGradient) return;
  // s h (3 − 6f) = s (A − 2fA)
  c->w = V::FmAdd(sh, V::FnmAdd(V::Set(3.0), two_f, V::Set(3.0)), c->w);
  // s h (Σx − 6 f c_sub) with 6 c_sub = (6 − 2a − 2b) x_L + 2a x_J + 2b x_K: the
  // weights w_m of the corners m = 0..2 serve x and y alike.
  const D two_a = z.a + z.a, two_b = z.b + z.b;
  const D w_l = (V::Set(6.0) - two_a) - two_b;
  // 1 − f w_m: corner m is L, J or K as L is 0, 1 or 2.
  const D one = V::Set(1.0);
  const D q_l = V::FnmAdd(z.f, w_l, one), q_j = V::FnmAdd(z.f, two_a, one),
          q_k = V::FnmAdd(z.f, two_b, one);
  const D q0 = Select3<V>(z.l1, z.l2, q_l, q_k, q_j);
  const D q1 = Select3<V>(z.l1, z.l2, q_j, q_l, q_k);
  const D q2 = Select3<V>(z.l1, z.l2, q_k, q_j, q_l);
  const D mx = V::FmAdd(q2, x2, V::FmAdd(q1, x1, q0 * x0));
  const D my = V::FmAdd(q2, y2, V::FmAdd(q1, y1, q0 * y0));
  c->mx = V::FmAdd(sh, mx, c->mx);
  c->my = V::FmAdd(sh, my, c->my);
}

// What FanWeighted's moments share (x and y alike).
template <class V>
struct WeightedFanCommon {
  LoneSign<V> z;
  typename V::D m0, m1, m2, ml, mp, mq, sm, sm_sub, two_f, st;
};

// s(∫μg − 2∫_sub μg) for g = x or y (corner values g0..g2): Σ m_i g_i + Σm
// Σg over (0, 1, 2) and over (L, P, Q).
template <class V>
inline typename V::D WeightedMoment(const WeightedFanCommon<V>& w, typename V::D g0,
                                    typename V::D g1, typename V::D g2) {
  using D = typename V::D;
  const D gl = Select3<V>(w.z.l1, w.z.l2, g0, g1, g2);
  const D gj = Select3<V>(w.z.l1, w.z.l2, g1, g2, g0);
  const D gk = Select3<V>(w.z.l1, w.z.l2, g2, g0, g1);
  const D gp = V::FmAdd(w.z.a, gj - gl, gl);
  const D gq = V::FmAdd(w.z.b, gk - gl, gl);
  const D sg = (g0 + g1) + g2;
  const D whole = V::FmAdd(w.sm, sg, V::FmAdd(w.m2, g2, V::FmAdd(w.m1, g1, w.m0 * g0)));
  const D sg_sub = (gl + gp) + gq;
  const D sub = V::FmAdd(w.sm_sub, sg_sub, V::FmAdd(w.mq, gq, V::FmAdd(w.mp, gp, w.ml * gl)));
  return w.st * V::FnmAdd(w.two_f, sub, whole);
}

// Fan with weights: μ linear on the triangle (corner values m0..m2). Per
// triangle of twice-area t, ∫μ = tΣm/6, ∫μg = t(Σ m_i g_i + Σm Σg)/24 for
// g linear (d, x, y); the cut-off part has corners (L, P, Q), P = L + a(J −
// L), Q = L + b(K − L), twice-area f·t, d values (d_L, 0, 0), and μ, x, y
// linear along its edges. ∫μ|d| = s(∫μd − 2∫_sub μd), ∫μ over the whole
// triangle (unsigned: the cell's weighted area), moments s(whole − 2 sub).
template <class V, bool kGradient>
inline void FanWeighted(typename V::D x0, typename V::D y0, typename V::D d0, typename V::D m0,
                        typename V::D x1, typename V::D y1, typename V::D d1, typename V::D m1,
                        typename V::D x2, typename V::D y2, typename V::D d2, typename V::D m2,
                        CellSums<V>* c) {
  using D = typename V::D;
  const D t = TwiceAreaOf<V>(x0, y0, x1, y1, x2, y2);
  c->twice = c->twice + t;
  const LoneSign<V> z = SplitOf<V>(d0, d1, d2);
  const D sm = (m0 + m1) + m2;
  c->mu = V::FmAdd(t * V::Set(1.0 / 6.0), sm, c->mu);
  // μ at L, J, K and at the cut points P, Q.
  const D ml = Select3<V>(z.l1, z.l2, m0, m1, m2);
  const D mj = Select3<V>(z.l1, z.l2, m1, m2, m0);
  const D mk = Select3<V>(z.l1, z.l2, m2, m0, m1);
  const D mp = V::FmAdd(z.a, mj - ml, ml);
  const D mq = V::FmAdd(z.b, mk - ml, ml);
  const D sm_sub = (ml + mp) + mq;
  const D two_f = z.f + z.f;
  const D st = z.s * (t * V::Set(1.0 / 24.0));
  // Σ m_i d_i + Σm Σd, whole and sub (d_L (m_L + Σm_sub) there).
  const D sd = (d0 + d1) + d2;
  const D wd = V::FmAdd(sm, sd, V::FmAdd(m2, d2, V::FmAdd(m1, d1, m0 * d0)));
  const D wd_sub = z.dl * (ml + sm_sub);
  c->abs = V::FmAdd(st, V::FnmAdd(two_f, wd_sub, wd), c->abs);
  if (!kGradient) return;
  // s t/6 (Σm − 2 f Σm_sub) = s (∫μ − 2 ∫_sub μ)
  c->w = V::FmAdd(st * V::Set(4.0), V::FnmAdd(two_f, sm_sub, sm), c->w);
  const WeightedFanCommon<V> w{z, m0, m1, m2, ml, mp, mq, sm, sm_sub, two_f, st};
  c->mx = c->mx + WeightedMoment<V>(w, x0, x1, x2);
  c->my = c->my + WeightedMoment<V>(w, y0, y1, y2);
}

// What a batch loads from the triangles' records.
template <class V>
struct Gathered {
  typename V::D ax[3], ay[3], bx[3], by[3];
  typename V::D ga_x, ga_y, fb_x, fb_y, za0, zb0;
  typename V::M swap_a[3], swap_b[3];
  typename V::M hull;  // lanes whose B triangle has a hull edge
};

template <class V>
inline void GatherBatch(const CellKernelInput& in, const Batch<V>& batch, Gathered<V>* g) {
  typename V::D f[8];
  V::LoadRecords(in.record_a, batch.ta, f);
  for (int k = 0; k < 3; ++k) g->ax[k] = f[k], g->ay[k] = f[3 + k];
  g->ga_x = f[6];
  g->ga_y = f[7];
  V::LoadRecords(in.record_b, batch.tb, f);
  for (int k = 0; k < 3; ++k) g->bx[k] = f[k], g->by[k] = f[3 + k];
  g->fb_x = f[6];
  g->fb_y = f[7];
  typename V::I bits_b;
  V::LoadExtras(in.extra_b, batch.tb, &g->zb0, &bits_b);
  g->za0 = V::Load(batch.za0);
  const typename V::I bits_a = V::LoadInt(batch.bits_a);
  g->swap_a[0] = V::template TestBit<0>(bits_a);
  g->swap_a[1] = V::template TestBit<1>(bits_a);
  g->swap_a[2] = V::template TestBit<2>(bits_a);
  g->swap_b[0] = V::template TestBit<0>(bits_b);
  g->swap_b[1] = V::template TestBit<1>(bits_b);
  g->swap_b[2] = V::template TestBit<2>(bits_b);
  static_assert(kHullBit == 1u << 3, "TestBit<3> below");
  g->hull = V::template TestBit<3>(bits_b);
}

// T_A's edges from their lower-index endpoints (e0 + t e, as CellCorners)
// and T_B's as endpoint pairs (r, s), per lane.
template <class V>
struct BatchEdges {
  typename V::D e0x[3], e0y[3], ex[3], ey[3], rx[3], ry[3], sx[3], sy[3];
};

template <class V>
inline BatchEdges<V> EdgesOf(const Gathered<V>& g) {
  using M = typename V::M;
  static constexpr int kFirst[3] = {1, 2, 0}, kSecond[3] = {2, 0, 1};  // edge i: opposite corner i
  BatchEdges<V> e;
  for (int i = 0; i < 3; ++i) {
    const int p = kFirst[i], q = kSecond[i];
    const M swap_a = g.swap_a[i];
    e.e0x[i] = V::Blend(swap_a, g.ax[p], g.ax[q]);
    e.e0y[i] = V::Blend(swap_a, g.ay[p], g.ay[q]);
    e.ex[i] = V::Blend(swap_a, g.ax[q], g.ax[p]) - e.e0x[i];
    e.ey[i] = V::Blend(swap_a, g.ay[q], g.ay[p]) - e.e0y[i];
    const M swap_b = g.swap_b[i];
    e.rx[i] = V::Blend(swap_b, g.bx[p], g.bx[q]);
    e.ry[i] = V::Blend(swap_b, g.by[p], g.by[q]);
    e.sx[i] = V::Blend(swap_b, g.bx[q], g.bx[p]);
    e.sy[i] = V::Blend(swap_b, g.by[q], g.by[p]);
  }
  return e;
}

// Where T_A's edge (i1, i2) crosses T_B's edge (j1, j2), per lane (t
// clamped to [0, 1]; parallel edges: the midpoint), as the scalar kernel.
template <class V>
inline void Crossing(const BatchEdges<V>& e, typename V::M i1, typename V::M i2, typename V::M j1,
                     typename V::M j2, typename V::D* cx, typename V::D* cy) {
  using D = typename V::D;
  const D zero = V::Zero(), one = V::Set(1.0), half = V::Set(0.5);
  const D e0x = Select3<V>(i1, i2, e.e0x[0], e.e0x[1], e.e0x[2]);
  const D e0y = Select3<V>(i1, i2, e.e0y[0], e.e0y[1], e.e0y[2]);
  const D ex = Select3<V>(i1, i2, e.ex[0], e.ex[1], e.ex[2]);
  const D ey = Select3<V>(i1, i2, e.ey[0], e.ey[1], e.ey[2]);
  const D rx = Select3<V>(j1, j2, e.rx[0], e.rx[1], e.rx[2]);
  const D ry = Select3<V>(j1, j2, e.ry[0], e.ry[1], e.ry[2]);
  const D sx = Select3<V>(j1, j2, e.sx[0], e.sx[1], e.sx[2]);
  const D sy = Select3<V>(j1, j2, e.sy[0], e.sy[1], e.sy[2]);
  const D vr = ex * (ry - e0y) - ey * (rx - e0x);
  const D vs = ex * (sy - e0y) - ey * (sx - e0x);
  const D den = vr - vs;
  D t = V::MaskDiv(half, V::Neq(den, zero), vr, den);
  t = V::Min(V::Max(t, zero), one);
  *cx = rx + t * (sx - rx);
  *cy = ry + t * (sy - ry);
}

// Run's sums over its batches, per lane: ∫μ|d| and ∫μ, and the interior
// sums (InteriorSums) before their reduction.
template <class V>
struct RunSums {
  typename V::D abs, area;
  typename V::D rotation[3], translation[3];
};

// A cell's interior share (volume_kernel_simd.h) into r[0..2], t[0..2]: its
// W, X, Y; its B triangle's ∇F̂ (gx, gy) and corner 0 less the offset (q0).
template <class T>
inline void AddShare(T w, T x, T y, T gx, T gy, T qx, T qy, T qz, T* r, T* t) {
  const T gxy = gx * gy;
  r[0] = r[0] + ((w * ((T{} - gy * qz) - qy) - x * gxy) - y * (gy * gy + 1.0));
  r[1] = r[1] + ((w * (qx + gx * qz) + x * (gx * gx + 1.0)) + y * gxy);
  r[2] = r[2] + ((w * (gy * qx - gx * qy) + x * gy) - y * gx);
  t[0] = t[0] - w * gx;
  t[1] = t[1] - w * gy;
  t[2] = t[2] + w;
}

// A batch's sums into Run's, with its cells' interior shares (and their
// bins'); the hull cells' boundary term.
template <class V, bool kGradient, bool kWeighted>
inline void AddBatch(const CellKernelInput& in, const Gathered<V>& g, const Batch<V>& batch, const CellSums<V>& c,
                     RunSums<V>* sums) {
  using D = typename V::D;
  using M = typename V::M;
  const D zero = V::Zero(), half = V::Set(0.5);
  const M active = V::FirstLanes(batch.size);
  // As the scalar kernel: every cell's area (∫μ); ∫μ|d| and the interior
  // shares of the cells of positive area only.
  const M valid = V::And(V::Gt(c.twice, zero), active);
  sums->abs = V::Blend(valid, sums->abs, sums->abs + V::Max(c.abs, zero));
  sums->area = V::Blend(active, sums->area, sums->area + (kWeighted ? c.mu : c.twice * half));
  if (kGradient) {
    const D w = V::MaskZ(valid, c.w), x = V::MaskZ(valid, c.mx), y = V::MaskZ(valid, c.my);
    const D qx = g.bx[0] - V::Set(in.offset[0]), qy = g.by[0] - V::Set(in.offset[1]);
    const D qz = g.zb0 - V::Set(in.offset[2]);
    AddShare<D>(w, x, y, g.fb_x, g.fb_y, qx, qy, qz, sums->rotation, sums->translation);
    if (in.bins.sums != nullptr) {  // rare: the sandwich's σ
      alignas(64) double lane[8][V::kLanes];
      const D values[8] = {w, x, y, g.fb_x, g.fb_y, qx, qy, qz};
      for (int k = 0; k < 8; ++k) V::Store(lane[k], values[k]);
      for (int l = 0; l < batch.size; ++l) {
        const int32_t b = in.bins.bin_of_b[batch.tb[l]];
        double* bin = in.bins.sums + 6 * static_cast<int64_t>(b);
        AddShare<double>(lane[0][l], lane[1][l], lane[2][l], lane[3][l], lane[4][l], lane[5][l], lane[6][l],
                         lane[7][l], bin, bin + 3);
        in.bins.used[b] = 1;
      }
    }
    // The hull cells' boundary term (scalar, rare).
    for (unsigned hull = V::Bits(V::And(g.hull, active)); hull != 0; hull &= hull - 1) {
      const int l = __builtin_ctz(hull);
      in.on_hull(in.context, batch.ta[l], batch.tb[l], batch.n[l]);
    }
  }
}

// The cells of one batch: corners as the scalar kernel computes them (same
// arithmetic, no contraction, so a shared crossing is the same point in
// every cell), then the fan integrals. kSlots: the corner count of every
// lane, or 0 for the batch's largest (shorter lanes padded).
template <class V, bool kGradient, bool kWeighted, int kSlots>
inline void RunBatch(const CellKernelInput& in, const Gathered<V>& g, const Batch<V>& batch, RunSums<V>* sums) {
  using D = typename V::D;
  using M = typename V::M;
  const D* ax = g.ax;
  const D* ay = g.ay;
  const D* bx = g.bx;
  const D* by = g.by;
  const BatchEdges<V> e = EdgesOf(g);
  // d = d0 + ∇d · (x, y) relative to T_B's corner 0.
  const D plane_a = (g.za0 + g.ga_x * (bx[0] - ax[0])) + g.ga_y * (by[0] - ay[0]);
  const D dd0 = g.zb0 - plane_a;
  const D dgx = g.fb_x - g.ga_x, dgy = g.fb_y - g.ga_y;
  // μ = μ0 + ∇μ · (x, y) likewise (unused unless kWeighted).
  D mu0 = V::Zero(), mu_gx = mu0, mu_gy = mu0;
  if (kWeighted) {
    mu_gx = V::Load(batch.mu_gx);
    mu_gy = V::Load(batch.mu_gy);
    mu0 = (V::Load(batch.mu0) + mu_gx * (bx[0] - ax[0])) + mu_gy * (by[0] - ay[0]);
  }

  const D zero = V::Zero();
  typename V::I code = V::LoadInt(batch.code);
  CellSums<V> c{zero, zero, zero, zero, zero, zero};
  D x0 = zero, y0 = zero, d0 = zero, xp = zero, yp = zero, dp = zero, m0 = zero, mp = zero;
  const int slots = kSlots > 0 ? kSlots : batch.max_n;
  for (int k = 0; k < slots; ++k) {
    // Kind 0..2 and indices 0..2: each value is one bit of the code.
    const M is_b = V::template TestBit<0>(code);
    const M is_cross = V::template TestBit<1>(code);
    const M i1 = V::template TestBit<2>(code), i2 = V::template TestBit<3>(code);
    const M j1 = V::template TestBit<4>(code), j2 = V::template TestBit<5>(code);
    code = V::Shift8(code);
    // Every corner as if a crossing, then the vertex corners picked instead.
    D cx, cy;
    Crossing<V>(e, i1, i2, j1, j2, &cx, &cy);
    const D vx = V::Blend(is_b, Select3<V>(i1, i2, ax[0], ax[1], ax[2]),
                          Select3<V>(i1, i2, bx[0], bx[1], bx[2]));
    const D vy = V::Blend(is_b, Select3<V>(i1, i2, ay[0], ay[1], ay[2]),
                          Select3<V>(i1, i2, by[0], by[1], by[2]));
    const D x = V::Blend(is_cross, vx, cx) - bx[0];
    const D y = V::Blend(is_cross, vy, cy) - by[0];
    const D d = (dd0 + dgx * x) + dgy * y;
    if (kWeighted) {
      const D m = (mu0 + mu_gx * x) + mu_gy * y;
      if (k == 0) {
        x0 = x, y0 = y, d0 = d, m0 = m;
      } else if (k >= 2) {
        FanWeighted<V, kGradient>(x0, y0, d0, m0, xp, yp, dp, mp, x, y, d, m, &c);
      }
      mp = m;
    } else if (k == 0) {
      x0 = x, y0 = y, d0 = d;
    } else if (k >= 2) {
      Fan<V, kGradient>(x0, y0, d0, xp, yp, dp, x, y, d, &c);
    }
    xp = x, yp = y, dp = d;
  }
  AddBatch<V, kGradient, kWeighted>(in, g, batch, c, sums);
}

template <class V, bool kGradient, bool kWeighted, int kSlots>
void Flush(const CellKernelInput& in, Batch<V>* batch, RunSums<V>* sums) {
  if (batch->size > 0) {
    // Idle lanes (the last batch only) repeat lane 0, masked out of the sums.
    for (int l = batch->size; l < V::kLanes; ++l) {
      batch->ta[l] = batch->ta[0];
      batch->tb[l] = batch->tb[0];
      batch->code[l] = batch->code[0];
      batch->za0[l] = batch->za0[0];
      batch->bits_a[l] = batch->bits_a[0];
      batch->mu0[l] = batch->mu0[0];
      batch->mu_gx[l] = batch->mu_gx[0];
      batch->mu_gy[l] = batch->mu_gy[0];
      batch->n[l] = batch->n[0];
    }
    Gathered<V> g;
    GatherBatch<V>(in, *batch, &g);
    RunBatch<V, kGradient, kWeighted, kSlots>(in, g, *batch, sums);
  }
  batch->size = 0;
  batch->max_n = 0;
}

// Cells in batches of one corner count (3, 4, 5; 6 to 8 padded): the corner
// counts vary, and a mixed batch would run every lane to the largest.
template <class V, bool kGradient, bool kWeighted>
void Run(const CellKernelInput& in, int32_t lo, int32_t hi, CellKernelOutput* out) {
  constexpr int kLanes = V::kLanes;
  Batch<V> batches[4];
  RunSums<V> sums;
  sums.abs = sums.area = V::Zero();
  for (int k = 0; k < 3; ++k) sums.rotation[k] = sums.translation[k] = V::Zero();
  auto flush = [&](int bucket) {
    switch (bucket) {
      case 0: Flush<V, kGradient, kWeighted, 3>(in, &batches[0], &sums); break;
      case 1: Flush<V, kGradient, kWeighted, 4>(in, &batches[1], &sums); break;
      case 2: Flush<V, kGradient, kWeighted, 5>(in, &batches[2], &sums); break;
      default: Flush<V, kGradient, kWeighted, 0>(in, &batches[3], &sums); break;
    }
  };
  // Lanes filled per bucket, 8 bits each, in a register: through memory,
  // every cell would wait on the previous one's store.
  uint32_t sizes = 0;
  int64_t cells = 0;
  for (int32_t ta = lo; ta < hi; ++ta) {
    const int32_t count = in.cell_count[ta];
    const TopologyCell* list = in.cells + in.cell_begin[ta];
    const double za0 = in.extra_a[ta].z0;
    const uint64_t bits_a = in.extra_a[ta].bits;
    double mu_m0 = 0, mu_gx = 0, mu_gy = 0;
    if (kWeighted) {
      const WeightPlane& mu = in.weight_a[ta];
      mu_m0 = mu.m0, mu_gx = mu.gx, mu_gy = mu.gy;
    }
    cells += count;
    for (int32_t c = 0; c < count; ++c) {
      const TopologyCell& tc = list[c];
      const int32_t tb = tc.triangle_b;
      const int n = tc.num_corners;
      // Fetched now, used when the batch is full.
      __builtin_prefetch(in.record_b + tb);
      __builtin_prefetch(in.extra_b + tb);
      uint64_t code;
      static_assert(sizeof(tc.corner) == sizeof(code), "8 corner codes");
      __builtin_memcpy(&code, &tc.corner, sizeof(code));
      const int bucket = n >= 3 && n <= 5 ? n - 3 : 3;
      const int shift = 8 * bucket;
      const int lane = (sizes >> shift) & 0xff;
      Batch<V>& batch = batches[bucket];
      if (bucket == 3) {
        if (n < 8 && n > 0) {
          const uint64_t last = (code >> (8 * (n - 1))) & 0xff;
          const uint64_t pad = ~uint64_t{0} << (8 * n);
          code = (code & ~pad) | ((last * 0x0101010101010101ull) & pad);
        }
        batch.max_n = lane == 0 || n > batch.max_n ? n : batch.max_n;
      }
      batch.ta[lane] = ta;
      batch.tb[lane] = tb;
      batch.code[lane] = code;
      batch.za0[lane] = za0;
      batch.bits_a[lane] = bits_a;
      if (kWeighted) {
        batch.mu0[lane] = mu_m0;
        batch.mu_gx[lane] = mu_gx;
        batch.mu_gy[lane] = mu_gy;
      }
      batch.n[lane] = static_cast<uint8_t>(n);
      sizes += 1u << shift;
      if (lane + 1 == kLanes) {
        batch.size = kLanes;
        flush(bucket);
        sizes &= ~(0xffu << shift);
      }
    }
  }
  for (int bucket = 0; bucket < 4; ++bucket) {
    batches[bucket].size = (sizes >> (8 * bucket)) & 0xff;
    flush(bucket);
  }
  out->abs = V::ReduceAdd(sums.abs);
  out->area = V::ReduceAdd(sums.area);
  out->cells = cells;
  if (kGradient) {
    for (int k = 0; k < 3; ++k) {
      out->interior.rotation[k] = V::ReduceAdd(sums.rotation[k]);
      out->interior.translation[k] = V::ReduceAdd(sums.translation[k]);
    }
  }
}

// IntegrateCellsSimd's work on lane type V.
template <class V>
void IntegrateCells(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                    CellKernelOutput* out) {
  const bool weighted = in.weight_a != nullptr;
  if (gradient && weighted) {
    Run<V, true, true>(in, lo, hi, out);
  } else if (gradient) {
    Run<V, true, false>(in, lo, hi, out);
  } else if (weighted) {
    Run<V, false, true>(in, lo, hi, out);
  } else {
    Run<V, false, false>(in, lo, hi, out);
  }
}

}  // namespace
}  // namespace volume_internal
}  // namespace surfreg

#include "registration/volume_kernel_simd.h"

#include <algorithm>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#if !defined(__clang__)
// GCC 12's AVX-512 headers seed masked intrinsics with a self-initialized
// "undefined" vector, which -Wuninitialized reports at every use.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>
#define SURFREG_HAVE_AVX512_KERNEL 1
#endif

namespace surfreg {
namespace volume_internal {

#ifdef SURFREG_HAVE_AVX512_KERNEL

bool CellKernelAvailable() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512vl");
}

namespace {

#define SURFREG_AVX512 __attribute__((target("avx512f,avx512dq,avx512vl,avx2,fma")))

constexpr int kLanes = 8;

// Up to 8 cells, one per lane. Corner codes are padded past num_corners
// with the last corner: a repeated corner makes zero-area fan triangles
// (exactly: the file is built without FP contraction), which add nothing.
struct Batch {
  alignas(64) int32_t ta[kLanes];
  alignas(64) int32_t tb[kLanes];
  alignas(64) uint64_t code[kLanes];
  alignas(64) double za0[kLanes];     // T_A's extras, copied per A triangle
  alignas(32) uint32_t bits_a[kLanes];
  alignas(64) double mu0[kLanes], mu_gx[kLanes], mu_gy[kLanes];  // T_A's μ plane (weighted)
  uint8_t n[kLanes];
  int size = 0;
  int max_n = 0;
};

// Per-lane accumulators of one batch of cells.
struct CellSums {
  __m512d abs, w, mx, my, twice;
  __m512d mu;  // ∫μ (weighted only)
};

SURFREG_AVX512 inline __m512d Select3(__mmask8 is1, __mmask8 is2, __m512d v0, __m512d v1,
                                      __m512d v2) {
  return _mm512_mask_blend_pd(is2, _mm512_mask_blend_pd(is1, v0, v1), v2);
}

// Where d = 0 cuts a fan triangle (d0, d1, d2), branch-free: the corner L
// whose sign is alone (the positive one if alone, else the negative one;
// l1/l2 select corner 1/2, (L, J, K) keeps the orientation), a = d_L/(d_L −
// d_J), b = d_L/(d_L − d_K) (zero where d has one sign), f = a·b the area
// fraction of the part (L, L + a(J − L), L + b(K − L)) cut off, and s the
// sign of the rest.
struct LoneSign {
  __mmask8 l1, l2;
  __m512d dl, a, b, f, s;
};

SURFREG_AVX512 inline LoneSign SplitOf(__m512d d0, __m512d d1, __m512d d2) {
  const __m512d zero = _mm512_setzero_pd();
  const __mmask8 p0 = _mm512_cmp_pd_mask(d0, zero, _CMP_GT_OQ);
  const __mmask8 p1 = _mm512_cmp_pd_mask(d1, zero, _CMP_GT_OQ);
  const __mmask8 p2 = _mm512_cmp_pd_mask(d2, zero, _CMP_GT_OQ);
  const __mmask8 n0 = _mm512_cmp_pd_mask(d0, zero, _CMP_LT_OQ);
  const __mmask8 n1 = _mm512_cmp_pd_mask(d1, zero, _CMP_LT_OQ);
  const __mmask8 n2 = _mm512_cmp_pd_mask(d2, zero, _CMP_LT_OQ);
  const __mmask8 any_pos = p0 | p1 | p2, any_neg = n0 | n1 | n2;
  const __mmask8 split = any_pos & any_neg;
  const __mmask8 one_pos = (p0 ^ p1 ^ p2) & ~(p0 & p1 & p2);
  LoneSign r;
  r.l1 = (one_pos & p1) | (~one_pos & n1);
  r.l2 = (one_pos & p2) | (~one_pos & n2);
  r.dl = Select3(r.l1, r.l2, d0, d1, d2);
  const __m512d dj = Select3(r.l1, r.l2, d1, d2, d0);
  const __m512d dk = Select3(r.l1, r.l2, d2, d0, d1);
  // Split lanes only: there d_L − d_J, d_L − d_K ≠ 0 (opposite signs or
  // zero). One division for both.
  const __m512d lj = _mm512_sub_pd(r.dl, dj), lk = _mm512_sub_pd(r.dl, dk);
  const __m512d q = _mm512_maskz_div_pd(split, r.dl, _mm512_mul_pd(lj, lk));
  r.a = _mm512_mul_pd(q, lk);
  r.b = _mm512_mul_pd(q, lj);
  r.f = _mm512_mul_pd(r.a, r.b);
  const __mmask8 s_pos = (any_pos & ~split) | (split & ~one_pos);
  const __mmask8 s_neg = (any_neg & ~split) | (split & one_pos);
  r.s = _mm512_mask_mov_pd(_mm512_maskz_mov_pd(s_neg, _mm512_set1_pd(-1.0)), s_pos,
                           _mm512_set1_pd(1.0));
  return r;
}

SURFREG_AVX512 inline __m512d TwiceAreaOf(__m512d x0, __m512d y0, __m512d x1, __m512d y1,
                                          __m512d x2, __m512d y2) {
  return _mm512_sub_pd(_mm512_mul_pd(_mm512_sub_pd(x1, x0), _mm512_sub_pd(y2, y0)),
                       _mm512_mul_pd(_mm512_sub_pd(y1, y0), _mm512_sub_pd(x2, x0)));
}

// One fan triangle (p0, p1, p2) with d linear on it: the whole triangle's
// ∫d, area and first moment, minus twice those of the part cut off by d = 0
// (SplitOf), times s: ∫|d|, and the signed area and moment.
template <bool kGradient>
SURFREG_AVX512 inline void Fan(__m512d x0, __m512d y0, __m512d d0, __m512d x1, __m512d y1,
                               __m512d d1, __m512d x2, __m512d y2, __m512d d2, CellSums* c) {
  const __m512d t = TwiceAreaOf(x0, y0, x1, y1, x2, y2);
  c->twice = _mm512_add_pd(c->twice, t);
  const __m512d h = _mm512_mul_pd(t, _mm512_set1_pd(1.0 / 6.0));
  const __m512d sd = _mm512_add_pd(_mm512_add_pd(d0, d1), d2);
  const LoneSign z = SplitOf(d0, d1, d2);
  const __mmask8 l1 = z.l1, l2 = z.l2;
  const __m512d a = z.a, b = z.b, f = z.f;
  const __m512d sh = _mm512_mul_pd(z.s, h);
  const __m512d two_f = _mm512_add_pd(f, f);
  // s h (Σd − 2 f d_L) = s (∫d − 2 ∫_sub d)
  c->abs = _mm512_fmadd_pd(sh, _mm512_fnmadd_pd(two_f, z.dl, sd), c->abs);
  if (!kGradient) return;
  // s h (3 − 6f) = s (A − 2fA)
  c->w = _mm512_fmadd_pd(sh, _mm512_fnmadd_pd(_mm512_set1_pd(3.0), two_f, _mm512_set1_pd(3.0)),
                         c->w);
  // s h (Σx − 6 f c_sub) with 6 c_sub = (6 − 2a − 2b) x_L + 2a x_J + 2b x_K: the
  // weights w_m of the corners m = 0..2 serve x and y alike.
  const __m512d two_a = _mm512_add_pd(a, a), two_b = _mm512_add_pd(b, b);
  const __m512d w_l = _mm512_sub_pd(_mm512_sub_pd(_mm512_set1_pd(6.0), two_a), two_b);
  // 1 − f w_m: corner m is L, J or K as L is 0, 1 or 2.
  const __m512d one = _mm512_set1_pd(1.0);
  const __m512d q_l = _mm512_fnmadd_pd(f, w_l, one), q_j = _mm512_fnmadd_pd(f, two_a, one),
                q_k = _mm512_fnmadd_pd(f, two_b, one);
  const __m512d q0 = Select3(l1, l2, q_l, q_k, q_j);
  const __m512d q1 = Select3(l1, l2, q_j, q_l, q_k);
  const __m512d q2 = Select3(l1, l2, q_k, q_j, q_l);
  const __m512d mx = _mm512_fmadd_pd(q2, x2, _mm512_fmadd_pd(q1, x1, _mm512_mul_pd(q0, x0)));
  const __m512d my = _mm512_fmadd_pd(q2, y2, _mm512_fmadd_pd(q1, y1, _mm512_mul_pd(q0, y0)));
  c->mx = _mm512_fmadd_pd(sh, mx, c->mx);
  c->my = _mm512_fmadd_pd(sh, my, c->my);
}

// What FanWeighted's moments share (x and y alike).
struct WeightedFanCommon {
  LoneSign z;
  __m512d m0, m1, m2, ml, mp, mq, sm, sm_sub, two_f, st;
};

// s(∫μg − 2∫_sub μg) for g = x or y (corner values g0..g2): Σ m_i g_i + Σm
// Σg over (0, 1, 2) and over (L, P, Q).
SURFREG_AVX512 inline __m512d WeightedMoment(const WeightedFanCommon& w, __m512d g0, __m512d g1,
                                             __m512d g2) {
  const __m512d gl = Select3(w.z.l1, w.z.l2, g0, g1, g2);
  const __m512d gj = Select3(w.z.l1, w.z.l2, g1, g2, g0);
  const __m512d gk = Select3(w.z.l1, w.z.l2, g2, g0, g1);
  const __m512d gp = _mm512_fmadd_pd(w.z.a, _mm512_sub_pd(gj, gl), gl);
  const __m512d gq = _mm512_fmadd_pd(w.z.b, _mm512_sub_pd(gk, gl), gl);
  const __m512d sg = _mm512_add_pd(_mm512_add_pd(g0, g1), g2);
  const __m512d whole = _mm512_fmadd_pd(
      w.sm, sg, _mm512_fmadd_pd(w.m2, g2, _mm512_fmadd_pd(w.m1, g1, _mm512_mul_pd(w.m0, g0))));
  const __m512d sg_sub = _mm512_add_pd(_mm512_add_pd(gl, gp), gq);
  const __m512d sub = _mm512_fmadd_pd(
      w.sm_sub, sg_sub,
      _mm512_fmadd_pd(w.mq, gq, _mm512_fmadd_pd(w.mp, gp, _mm512_mul_pd(w.ml, gl))));
  return _mm512_mul_pd(w.st, _mm512_fnmadd_pd(w.two_f, sub, whole));
}

// Fan with weights: μ linear on the triangle (corner values m0..m2). Per
// triangle of twice-area t, ∫μ = tΣm/6, ∫μg = t(Σ m_i g_i + Σm Σg)/24 for
// g linear (d, x, y); the cut-off part has corners (L, P, Q), P = L + a(J −
// L), Q = L + b(K − L), twice-area f·t, d values (d_L, 0, 0), and μ, x, y
// linear along its edges. ∫μ|d| = s(∫μd − 2∫_sub μd), ∫μ over the whole
// triangle (unsigned: the cell's weighted area), moments s(whole − 2 sub).
template <bool kGradient>
SURFREG_AVX512 inline void FanWeighted(__m512d x0, __m512d y0, __m512d d0, __m512d m0, __m512d x1,
                                       __m512d y1, __m512d d1, __m512d m1, __m512d x2,
                                       __m512d y2, __m512d d2, __m512d m2, CellSums* c) {
  const __m512d t = TwiceAreaOf(x0, y0, x1, y1, x2, y2);
  c->twice = _mm512_add_pd(c->twice, t);
  const LoneSign z = SplitOf(d0, d1, d2);
  const __m512d sm = _mm512_add_pd(_mm512_add_pd(m0, m1), m2);
  c->mu = _mm512_fmadd_pd(_mm512_mul_pd(t, _mm512_set1_pd(1.0 / 6.0)), sm, c->mu);
  // μ at L, J, K and at the cut points P, Q.
  const __m512d ml = Select3(z.l1, z.l2, m0, m1, m2);
  const __m512d mj = Select3(z.l1, z.l2, m1, m2, m0);
  const __m512d mk = Select3(z.l1, z.l2, m2, m0, m1);
  const __m512d mp = _mm512_fmadd_pd(z.a, _mm512_sub_pd(mj, ml), ml);
  const __m512d mq = _mm512_fmadd_pd(z.b, _mm512_sub_pd(mk, ml), ml);
  const __m512d sm_sub = _mm512_add_pd(_mm512_add_pd(ml, mp), mq);
  const __m512d two_f = _mm512_add_pd(z.f, z.f);
  const __m512d st = _mm512_mul_pd(z.s, _mm512_mul_pd(t, _mm512_set1_pd(1.0 / 24.0)));
  // Σ m_i d_i + Σm Σd, whole and sub (d_L (m_L + Σm_sub) there).
  const __m512d sd = _mm512_add_pd(_mm512_add_pd(d0, d1), d2);
  const __m512d wd = _mm512_fmadd_pd(
      sm, sd, _mm512_fmadd_pd(m2, d2, _mm512_fmadd_pd(m1, d1, _mm512_mul_pd(m0, d0))));
  const __m512d wd_sub = _mm512_mul_pd(z.dl, _mm512_add_pd(ml, sm_sub));
  c->abs = _mm512_fmadd_pd(st, _mm512_fnmadd_pd(two_f, wd_sub, wd), c->abs);
  if (!kGradient) return;
  // s t/6 (Σm − 2 f Σm_sub) = s (∫μ − 2 ∫_sub μ)
  c->w = _mm512_fmadd_pd(_mm512_mul_pd(st, _mm512_set1_pd(4.0)),
                         _mm512_fnmadd_pd(two_f, sm_sub, sm), c->w);
  const WeightedFanCommon w{z, m0, m1, m2, ml, mp, mq, sm, sm_sub, two_f, st};
  c->mx = _mm512_add_pd(c->mx, WeightedMoment(w, x0, x1, x2));
  c->my = _mm512_add_pd(c->my, WeightedMoment(w, y0, y1, y2));
}

SURFREG_AVX512 inline __m512d Gather(__m256i index, const double* base) {
  return _mm512_i32gather_pd(index, base, 8);
}

// What a batch loads from the triangles' records.
struct Gathered {
  __m512d ax[3], ay[3], bx[3], by[3];
  __m512d ga_x, ga_y, fb_x, fb_y, za0, zb0;
  __mmask8 swap_a[3], swap_b[3];
  __mmask8 hull;  // lanes whose B triangle has a hull edge
};

// 8 rows of 8 doubles (one per lane) to 8 vectors (one per field).
SURFREG_AVX512 inline void Transpose8(const TriangleRecord* base, const int32_t* index, __m512d out[8]) {
  __m512d r[8], u[8], v[8];
  for (int l = 0; l < 8; ++l) r[l] = _mm512_load_pd(base[index[l]].x);
  for (int l = 0; l < 8; l += 2) {
    u[l] = _mm512_unpacklo_pd(r[l], r[l + 1]);      // fields 0 2 4 6 of rows l, l+1
    u[l + 1] = _mm512_unpackhi_pd(r[l], r[l + 1]);  // fields 1 3 5 7
  }
  const __m512i lo = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
  const __m512i hi = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
  for (int l = 0; l < 8; l += 4) {
    for (int h = 0; h < 2; ++h) {
      v[l + h] = _mm512_permutex2var_pd(u[l + h], lo, u[l + 2 + h]);      // fields 0|1, 4|5 of rows l..l+3
      v[l + 2 + h] = _mm512_permutex2var_pd(u[l + h], hi, u[l + 2 + h]);  // fields 2|3, 6|7
    }
  }
  // v[0]: field 0 (rows 0-3), field 4; v[1]: 1, 5; v[2]: 2, 6; v[3]: 3, 7; v[4..7] rows 4-7.
  for (int f = 0; f < 4; ++f) {
    out[f] = _mm512_shuffle_f64x2(v[f], v[4 + f], 0x44);
    out[f + 4] = _mm512_shuffle_f64x2(v[f], v[4 + f], 0xee);
  }
}

SURFREG_AVX512 inline void GatherBatch(const CellKernelInput& in, const Batch& batch, Gathered* g) {
  __m512d f[8];
  Transpose8(in.record_a, batch.ta, f);
  for (int k = 0; k < 3; ++k) g->ax[k] = f[k], g->ay[k] = f[3 + k];
  g->ga_x = f[6];
  g->ga_y = f[7];
  Transpose8(in.record_b, batch.tb, f);
  for (int k = 0; k < 3; ++k) g->bx[k] = f[k], g->by[k] = f[3 + k];
  g->fb_x = f[6];
  g->fb_y = f[7];
  // Extras: 16 bytes per triangle.
  const __m256i tb = _mm256_load_si256(reinterpret_cast<const __m256i*>(batch.tb));
  const __m256i tb2 = _mm256_add_epi32(tb, tb);
  g->za0 = _mm512_load_pd(batch.za0);
  g->zb0 = Gather(tb2, &in.extra_b[0].z0);
  const int* swap_b = reinterpret_cast<const int*>(&in.extra_b[0].bits);
  const __m256i sa = _mm256_load_si256(reinterpret_cast<const __m256i*>(batch.bits_a));
  const __m256i sb = _mm256_i32gather_epi32(swap_b, _mm256_add_epi32(tb2, tb2), 4);
  for (int i = 0; i < 3; ++i) {
    const __m256i bit = _mm256_set1_epi32(1 << i);
    g->swap_a[i] = _mm256_test_epi32_mask(sa, bit);
    g->swap_b[i] = _mm256_test_epi32_mask(sb, bit);
  }
  g->hull = _mm256_test_epi32_mask(sb, _mm256_set1_epi32(kHullBit));
}

// The cells of one batch: corners as the scalar kernel computes them (same
// arithmetic, no contraction, so a shared crossing is the same point in
// every cell), then the fan integrals. kSlots: the corner count of every
// lane, or 0 for the batch's largest (shorter lanes padded).
template <bool kGradient, bool kWeighted, int kSlots>
SURFREG_AVX512 inline void RunBatch(const CellKernelInput& in, const Gathered& g, const Batch& batch,
                                    __m512d* total_abs, __m512d* total_area,
                                    std::array<double, 3>* moment) {
  const __mmask8 active = static_cast<__mmask8>((1u << batch.size) - 1);
  const __m512d* ax = g.ax;
  const __m512d* ay = g.ay;
  const __m512d* bx = g.bx;
  const __m512d* by = g.by;
  // Edge i (opposite corner i) from its lower-index endpoint, as CellCorners.
  static constexpr int kFirst[3] = {1, 2, 0}, kSecond[3] = {2, 0, 1};
  __m512d e0x[3], e0y[3], ex[3], ey[3], rx[3], ry[3], sx[3], sy[3];
  for (int i = 0; i < 3; ++i) {
    const int p = kFirst[i], q = kSecond[i];
    const __mmask8 swap_a = g.swap_a[i];
    e0x[i] = _mm512_mask_blend_pd(swap_a, ax[p], ax[q]);
    e0y[i] = _mm512_mask_blend_pd(swap_a, ay[p], ay[q]);
    ex[i] = _mm512_sub_pd(_mm512_mask_blend_pd(swap_a, ax[q], ax[p]), e0x[i]);
    ey[i] = _mm512_sub_pd(_mm512_mask_blend_pd(swap_a, ay[q], ay[p]), e0y[i]);
    const __mmask8 swap_b = g.swap_b[i];
    rx[i] = _mm512_mask_blend_pd(swap_b, bx[p], bx[q]);
    ry[i] = _mm512_mask_blend_pd(swap_b, by[p], by[q]);
    sx[i] = _mm512_mask_blend_pd(swap_b, bx[q], bx[p]);
    sy[i] = _mm512_mask_blend_pd(swap_b, by[q], by[p]);
  }
  // d = d0 + ∇d · (x, y) relative to T_B's corner 0.
  const __m512d ga_x = g.ga_x, ga_y = g.ga_y, fb_x = g.fb_x, fb_y = g.fb_y, za0 = g.za0, zb0 = g.zb0;
  const __m512d plane_a = _mm512_add_pd(
      _mm512_add_pd(za0, _mm512_mul_pd(ga_x, _mm512_sub_pd(bx[0], ax[0]))),
      _mm512_mul_pd(ga_y, _mm512_sub_pd(by[0], ay[0])));
  const __m512d dd0 = _mm512_sub_pd(zb0, plane_a);
  const __m512d dgx = _mm512_sub_pd(fb_x, ga_x), dgy = _mm512_sub_pd(fb_y, ga_y);
  // μ = μ0 + ∇μ · (x, y) likewise (unused unless kWeighted).
  __m512d mu0 = _mm512_setzero_pd(), mu_gx = mu0, mu_gy = mu0;
  if (kWeighted) {
    mu_gx = _mm512_load_pd(batch.mu_gx);
    mu_gy = _mm512_load_pd(batch.mu_gy);
    mu0 = _mm512_add_pd(
        _mm512_add_pd(_mm512_load_pd(batch.mu0), _mm512_mul_pd(mu_gx, _mm512_sub_pd(bx[0], ax[0]))),
        _mm512_mul_pd(mu_gy, _mm512_sub_pd(by[0], ay[0])));
  }

  const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0), half = _mm512_set1_pd(0.5);
  __m512i code = _mm512_load_si512(batch.code);
  CellSums c{zero, zero, zero, zero, zero, zero};
  __m512d x0 = zero, y0 = zero, d0 = zero, xp = zero, yp = zero, dp = zero, m0 = zero, mp = zero;
  const int slots = kSlots > 0 ? kSlots : batch.max_n;
  for (int k = 0; k < slots; ++k) {
    // Kind 0..2 and indices 0..2: each value is one bit of the code.
    const __mmask8 is_b = _mm512_test_epi64_mask(code, _mm512_set1_epi64(1));
    const __mmask8 is_cross = _mm512_test_epi64_mask(code, _mm512_set1_epi64(2));
    const __mmask8 i1 = _mm512_test_epi64_mask(code, _mm512_set1_epi64(1 << 2));
    const __mmask8 i2 = _mm512_test_epi64_mask(code, _mm512_set1_epi64(2 << 2));
    const __mmask8 j1 = _mm512_test_epi64_mask(code, _mm512_set1_epi64(1 << 4));
    const __mmask8 j2 = _mm512_test_epi64_mask(code, _mm512_set1_epi64(2 << 4));
    code = _mm512_srli_epi64(code, 8);
    // Every corner as if a crossing, then the vertex corners picked instead.
    const __m512d e0x_ = Select3(i1, i2, e0x[0], e0x[1], e0x[2]);
    const __m512d e0y_ = Select3(i1, i2, e0y[0], e0y[1], e0y[2]);
    const __m512d ex_ = Select3(i1, i2, ex[0], ex[1], ex[2]);
    const __m512d ey_ = Select3(i1, i2, ey[0], ey[1], ey[2]);
    const __m512d rx_ = Select3(j1, j2, rx[0], rx[1], rx[2]);
    const __m512d ry_ = Select3(j1, j2, ry[0], ry[1], ry[2]);
    const __m512d sx_ = Select3(j1, j2, sx[0], sx[1], sx[2]);
    const __m512d sy_ = Select3(j1, j2, sy[0], sy[1], sy[2]);
    const __m512d vr = _mm512_sub_pd(_mm512_mul_pd(ex_, _mm512_sub_pd(ry_, e0y_)),
                                     _mm512_mul_pd(ey_, _mm512_sub_pd(rx_, e0x_)));
    const __m512d vs = _mm512_sub_pd(_mm512_mul_pd(ex_, _mm512_sub_pd(sy_, e0y_)),
                                     _mm512_mul_pd(ey_, _mm512_sub_pd(sx_, e0x_)));
    const __m512d den = _mm512_sub_pd(vr, vs);
    const __mmask8 nonzero = _mm512_cmp_pd_mask(den, zero, _CMP_NEQ_UQ);
    __m512d t = _mm512_mask_div_pd(half, nonzero, vr, den);
    t = _mm512_min_pd(_mm512_max_pd(t, zero), one);
    const __m512d cx = _mm512_add_pd(rx_, _mm512_mul_pd(t, _mm512_sub_pd(sx_, rx_)));
    const __m512d cy = _mm512_add_pd(ry_, _mm512_mul_pd(t, _mm512_sub_pd(sy_, ry_)));
    const __m512d vx = _mm512_mask_blend_pd(is_b, Select3(i1, i2, ax[0], ax[1], ax[2]),
                                            Select3(i1, i2, bx[0], bx[1], bx[2]));
    const __m512d vy = _mm512_mask_blend_pd(is_b, Select3(i1, i2, ay[0], ay[1], ay[2]),
                                            Select3(i1, i2, by[0], by[1], by[2]));
    const __m512d x = _mm512_sub_pd(_mm512_mask_blend_pd(is_cross, vx, cx), bx[0]);
    const __m512d y = _mm512_sub_pd(_mm512_mask_blend_pd(is_cross, vy, cy), by[0]);
    const __m512d d = _mm512_add_pd(_mm512_add_pd(dd0, _mm512_mul_pd(dgx, x)), _mm512_mul_pd(dgy, y));
    if (kWeighted) {
      const __m512d m = _mm512_add_pd(_mm512_add_pd(mu0, _mm512_mul_pd(mu_gx, x)), _mm512_mul_pd(mu_gy, y));
      if (k == 0) {
        x0 = x, y0 = y, d0 = d, m0 = m;
      } else if (k >= 2) {
        FanWeighted<kGradient>(x0, y0, d0, m0, xp, yp, dp, mp, x, y, d, m, &c);
      }
      mp = m;
    } else if (k == 0) {
      x0 = x, y0 = y, d0 = d;
    } else if (k >= 2) {
      Fan<kGradient>(x0, y0, d0, xp, yp, dp, x, y, d, &c);
    }
    xp = x, yp = y, dp = d;
  }
  // As the scalar kernel: every cell's area (∫μ); ∫μ|d| and the moments of
  // the cells of positive area only.
  const __mmask8 valid = _mm512_cmp_pd_mask(c.twice, zero, _CMP_GT_OQ) & active;
  *total_abs = _mm512_mask_add_pd(*total_abs, valid, *total_abs, _mm512_max_pd(c.abs, zero));
  *total_area = _mm512_mask_add_pd(*total_area, active, *total_area,
                                   kWeighted ? c.mu : _mm512_mul_pd(c.twice, half));
  if (kGradient) {
    alignas(64) double w[kLanes], mx[kLanes], my[kLanes];
    _mm512_store_pd(w, _mm512_maskz_mov_pd(valid, c.w));
    _mm512_store_pd(mx, _mm512_maskz_mov_pd(valid, c.mx));
    _mm512_store_pd(my, _mm512_maskz_mov_pd(valid, c.my));
    // Scalar scatter: lanes may share a B triangle.
    for (int l = 0; l < batch.size; ++l) {
      std::array<double, 3>& m = moment[batch.tb[l]];
      m[0] += w[l];
      m[1] += mx[l];
      m[2] += my[l];
    }
    // The hull cells' boundary term (scalar, rare).
    for (unsigned hull = g.hull & active; hull != 0; hull &= hull - 1) {
      const int l = __builtin_ctz(hull);
      in.on_hull(in.context, batch.ta[l], batch.tb[l], batch.n[l]);
    }
  }
}

template <bool kGradient, bool kWeighted, int kSlots>
SURFREG_AVX512 void Flush(const CellKernelInput& in, Batch* batch, __m512d* total_abs,
                          __m512d* total_area, std::array<double, 3>* moment) {
  if (batch->size > 0) {
    // Idle lanes (the last batch only) repeat lane 0, masked out of the sums.
    for (int l = batch->size; l < kLanes; ++l) {
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
    Gathered g;
    GatherBatch(in, *batch, &g);
    RunBatch<kGradient, kWeighted, kSlots>(in, g, *batch, total_abs, total_area, moment);
  }
  batch->size = 0;
  batch->max_n = 0;
}

// Cells in batches of one corner count (3, 4, 5; 6 to 8 padded): the corner
// counts vary, and a mixed batch would run every lane to the largest.
template <bool kGradient, bool kWeighted>
SURFREG_AVX512 void Run(const CellKernelInput& in, int32_t lo, int32_t hi,
                        std::array<double, 3>* moment, CellKernelOutput* out) {
  const OverlayTopology& topology = *in.topology;
  Batch batches[4];
  __m512d total_abs = _mm512_setzero_pd(), total_area = _mm512_setzero_pd();
  auto flush = [&](int bucket) {
    switch (bucket) {
      case 0: Flush<kGradient, kWeighted, 3>(in, &batches[0], &total_abs, &total_area, moment); break;
      case 1: Flush<kGradient, kWeighted, 4>(in, &batches[1], &total_abs, &total_area, moment); break;
      case 2: Flush<kGradient, kWeighted, 5>(in, &batches[2], &total_abs, &total_area, moment); break;
      default: Flush<kGradient, kWeighted, 0>(in, &batches[3], &total_abs, &total_area, moment); break;
    }
  };
  // Lanes filled per bucket, 8 bits each, in a register: through memory,
  // every cell would wait on the previous one's store.
  uint32_t sizes = 0;
  int64_t cells = 0;
  for (int32_t ta = lo; ta < hi; ++ta) {
    const int32_t count = topology.count_of(ta);
    const TopologyCell* list = topology.cells_of(ta);
    const double za0 = in.extra_a[ta].z0;
    const uint32_t bits_a = in.extra_a[ta].bits;
    const WeightPlane mu = kWeighted ? in.weight_a[ta] : WeightPlane{};
    cells += count;
    for (int32_t c = 0; c < count; ++c) {
      const TopologyCell& tc = list[c];
      const int32_t tb = tc.triangle_b;
      const int n = tc.num_corners;
      // Fetched now, used when the batch is full.
      __builtin_prefetch(in.record_b + tb);
      __builtin_prefetch(in.extra_b + tb);
      if (kGradient) __builtin_prefetch(moment + tb, 1);
      uint64_t code;
      std::memcpy(&code, tc.corner.data(), sizeof(code));
      const int bucket = n >= 3 && n <= 5 ? n - 3 : 3;
      const int shift = 8 * bucket;
      const int lane = (sizes >> shift) & 0xff;
      Batch& batch = batches[bucket];
      if (bucket == 3) {
        if (n < 8 && n > 0) {
          const uint64_t last = (code >> (8 * (n - 1))) & 0xff;
          const uint64_t pad = ~uint64_t{0} << (8 * n);
          code = (code & ~pad) | ((last * 0x0101010101010101ull) & pad);
        }
        batch.max_n = lane == 0 ? n : std::max(batch.max_n, n);
      }
      batch.ta[lane] = ta;
      batch.tb[lane] = tb;
      batch.code[lane] = code;
      batch.za0[lane] = za0;
      batch.bits_a[lane] = bits_a;
      if (kWeighted) {
        batch.mu0[lane] = mu.m0;
        batch.mu_gx[lane] = mu.gx;
        batch.mu_gy[lane] = mu.gy;
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
  out->abs = _mm512_reduce_add_pd(total_abs);
  out->area = _mm512_reduce_add_pd(total_area);
  out->cells = cells;
}

}  // namespace

void IntegrateCellsSimd(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                        std::array<double, 3>* moment, CellKernelOutput* out) {
  const bool weighted = in.weight_a != nullptr;
  if (gradient) {
    weighted ? Run<true, true>(in, lo, hi, moment, out) : Run<true, false>(in, lo, hi, moment, out);
  } else {
    weighted ? Run<false, true>(in, lo, hi, moment, out) : Run<false, false>(in, lo, hi, moment, out);
  }
}

#else  // no vector kernel on this target

bool CellKernelAvailable() { return false; }
void IntegrateCellsSimd(const CellKernelInput&, int32_t, int32_t, bool, std::array<double, 3>*,
                        CellKernelOutput*) {}

#endif

}  // namespace volume_internal
}  // namespace surfreg

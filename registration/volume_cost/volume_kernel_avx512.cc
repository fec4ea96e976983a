// The vector cell kernel (volume_kernel_body.h) on AVX-512 F/DQ/VL: 8
// cells per vector. registration/CMakeLists.txt compiles this file alone
// with -mavx512f -mavx512dq -mavx512vl -mavx2 -mfma (x86-64 only); its one
// entry point runs only after volume_kernel_simd.cc's CPU check. Elsewhere
// it compiles to nothing.
#if defined(__x86_64__) && defined(__AVX512F__) && defined(__AVX512DQ__) && \
    defined(__AVX512VL__) && defined(__AVX2__) && defined(__FMA__)

#if defined(__GNUC__) && !defined(__clang__)
// GCC 12's AVX-512 headers seed masked intrinsics with a self-initialized
// "undefined" vector, which -Wuninitialized reports at every use.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <cstdint>

#include "registration/volume_cost/volume_kernel_simd.h"

namespace surfreg {
namespace volume_internal {
namespace {

// The lanes as volume_kernel_body.h wants them: masks are __mmask8.
struct Avx512 {
  using D = __m512d;
  using M = __mmask8;
  using I = __m512i;
  static constexpr int kLanes = 8;

  static D Set(double c) { return _mm512_set1_pd(c); }
  static D Zero() { return _mm512_setzero_pd(); }
  static D Load(const double* p) { return _mm512_load_pd(p); }
  static void Store(double* p, D x) { _mm512_store_pd(p, x); }
  static D Min(D a, D b) { return _mm512_min_pd(a, b); }
  static D Max(D a, D b) { return _mm512_max_pd(a, b); }
  static D FmAdd(D a, D b, D c) { return _mm512_fmadd_pd(a, b, c); }
  static D FnmAdd(D a, D b, D c) { return _mm512_fnmadd_pd(a, b, c); }

  static M Gt(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
  static M Lt(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  static M Neq(D a, D b) { return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ); }
  static M And(M a, M b) { return static_cast<M>(a & b); }
  static M Or(M a, M b) { return static_cast<M>(a | b); }
  static M Xor(M a, M b) { return static_cast<M>(a ^ b); }
  static M AndNot(M a, M b) { return static_cast<M>(~a & b); }
  static D Blend(M m, D a, D b) { return _mm512_mask_blend_pd(m, a, b); }
  static D MaskZ(M m, D a) { return _mm512_maskz_mov_pd(m, a); }
  static D MaskDiv(D src, M m, D a, D b) { return _mm512_mask_div_pd(src, m, a, b); }
  static M FirstLanes(int n) { return static_cast<M>((1u << n) - 1); }
  static unsigned Bits(M m) { return m; }
  static double ReduceAdd(D x) { return _mm512_reduce_add_pd(x); }

  static I LoadInt(const uint64_t* p) { return _mm512_load_si512(p); }
  static I Shift8(I x) { return _mm512_srli_epi64(x, 8); }
  template <int kBit>
  static M TestBit(I x) {
    return _mm512_test_epi64_mask(x, _mm512_set1_epi64(int64_t{1} << kBit));
  }

  // 8 records of 8 doubles (one per lane) to 8 vectors (one per field).
  static void LoadRecords(const TriangleRecord* base, const int32_t* index, D out[8]) {
    D r[8], u[8], v[8];
    for (int l = 0; l < 8; ++l) r[l] = _mm512_load_pd(base + index[l]);
    for (int l = 0; l < 8; l += 2) {
      u[l] = _mm512_unpacklo_pd(r[l], r[l + 1]);      // fields 0 2 4 6 of rows l, l+1
      u[l + 1] = _mm512_unpackhi_pd(r[l], r[l + 1]);  // fields 1 3 5 7
    }
    const __m512i lo = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
    const __m512i hi = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
    for (int l = 0; l < 8; l += 4) {
      for (int h = 0; h < 2; ++h) {
        // Fields 0|1, 4|5 of rows l..l+3, then 2|3, 6|7.
        v[l + h] = _mm512_permutex2var_pd(u[l + h], lo, u[l + 2 + h]);
        v[l + 2 + h] = _mm512_permutex2var_pd(u[l + h], hi, u[l + 2 + h]);
      }
    }
    // v[0]: field 0 (rows 0-3), field 4; v[1]: 1, 5; v[2]: 2, 6; v[3]: 3, 7; v[4..7] rows 4-7.
    for (int f = 0; f < 4; ++f) {
      out[f] = _mm512_shuffle_f64x2(v[f], v[4 + f], 0x44);
      out[f + 4] = _mm512_shuffle_f64x2(v[f], v[4 + f], 0xee);
    }
  }

  // Gathers, 16 bytes per triangle (index × 2 in units of 8 bytes).
  static void LoadExtras(const TriangleExtra* base, const int32_t* index, D* z0, I* bits) {
    const __m256i i = _mm256_load_si256(reinterpret_cast<const __m256i*>(index));
    const __m256i i2 = _mm256_add_epi32(i, i);
    *z0 = _mm512_i32gather_pd(i2, &base->z0, 8);
    *bits = _mm512_i32gather_epi64(i2, &base->bits, 8);
  }
};

}  // namespace
}  // namespace volume_internal
}  // namespace surfreg

#include "registration/volume_cost/volume_kernel_body.h"

namespace surfreg {
namespace volume_internal {

void IntegrateCellsAvx512(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                          CellKernelOutput* out) {
  IntegrateCells<Avx512>(in, lo, hi, gradient, out);
}

}  // namespace volume_internal
}  // namespace surfreg

#endif

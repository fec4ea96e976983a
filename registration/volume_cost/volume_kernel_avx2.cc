// The vector cell kernel (volume_kernel_body.h) on AVX2 + FMA: 4 cells per
// vector, for x86-64 CPUs without AVX-512. registration/CMakeLists.txt
// compiles this file alone with -mavx2 -mfma (x86-64 only); its one entry
// point runs only after volume_kernel_simd.cc's CPU check. Elsewhere it
// compiles to nothing.
#if defined(__x86_64__) && defined(__AVX2__) && defined(__FMA__)

#include <immintrin.h>

#include <cstdint>

#include "registration/volume_cost/volume_kernel_simd.h"

namespace surfreg {
namespace volume_internal {
namespace {

// The lanes as volume_kernel_body.h wants them. A mask is a vector whose
// lanes' sign bits are the flags: blendv and movemask read only those, and
// the bitwise mask operations keep them, so a code bit shifted into the sign
// position is a mask in one instruction.
struct Avx2 {
  using D = __m256d;
  using M = __m256d;
  using I = __m256i;
  static constexpr int kLanes = 4;

  static D Set(double c) { return _mm256_set1_pd(c); }
  static D Zero() { return _mm256_setzero_pd(); }
  static D Load(const double* p) { return _mm256_load_pd(p); }
  static void Store(double* p, D x) { _mm256_store_pd(p, x); }
  static D Min(D a, D b) { return _mm256_min_pd(a, b); }
  static D Max(D a, D b) { return _mm256_max_pd(a, b); }
  static D FmAdd(D a, D b, D c) { return _mm256_fmadd_pd(a, b, c); }
  static D FnmAdd(D a, D b, D c) { return _mm256_fnmadd_pd(a, b, c); }

  static M Gt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
  static M Lt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  static M Neq(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
  static M And(M a, M b) { return _mm256_and_pd(a, b); }
  static M Or(M a, M b) { return _mm256_or_pd(a, b); }
  static M Xor(M a, M b) { return _mm256_xor_pd(a, b); }
  static M AndNot(M a, M b) { return _mm256_andnot_pd(a, b); }
  static D Blend(M m, D a, D b) { return _mm256_blendv_pd(a, b, m); }
  static D MaskZ(M m, D a) { return _mm256_blendv_pd(_mm256_setzero_pd(), a, m); }
  static D MaskDiv(D src, M m, D a, D b) { return _mm256_blendv_pd(src, _mm256_div_pd(a, b), m); }
  static M FirstLanes(int n) {
    return _mm256_castsi256_pd(
        _mm256_cmpgt_epi64(_mm256_set1_epi64x(n), _mm256_setr_epi64x(0, 1, 2, 3)));
  }
  static unsigned Bits(M m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
  static double ReduceAdd(D x) {
    const __m128d s = _mm_add_pd(_mm256_castpd256_pd128(x), _mm256_extractf128_pd(x, 1));
    return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
  }

  static I LoadInt(const uint64_t* p) {
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
  }
  static I Shift8(I x) { return _mm256_srli_epi64(x, 8); }
  template <int kBit>
  static M TestBit(I x) {
    return _mm256_castsi256_pd(_mm256_slli_epi64(x, 63 - kBit));
  }

  // Rows 0 and 2, 1 and 3 paired in the 128-bit halves of two vectors, two
  // fields at a time; one unpack then gives each field across the 4 rows
  // (no lane-crossing shuffle).
  static void Pair(const double* r0, const double* r1, const double* r2, const double* r3,
                   D* even, D* odd) {
    const D u02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(r0)), _mm_load_pd(r2), 1);
    const D u13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(r1)), _mm_load_pd(r3), 1);
    *even = _mm256_unpacklo_pd(u02, u13);
    *odd = _mm256_unpackhi_pd(u02, u13);
  }

  static void LoadRecords(const TriangleRecord* base, const int32_t* index, D out[8]) {
    const double* r[4];
    for (int l = 0; l < 4; ++l) r[l] = reinterpret_cast<const double*>(base + index[l]);
    for (int f = 0; f < 8; f += 2) {
      Pair(r[0] + f, r[1] + f, r[2] + f, r[3] + f, &out[f], &out[f + 1]);
    }
  }

  // (z0, bits) of each triangle as two doubles' bits: plain loads instead
  // of gathers (slow on many AVX2 CPUs).
  static void LoadExtras(const TriangleExtra* base, const int32_t* index, D* z0, I* bits) {
    const double* r[4];
    for (int l = 0; l < 4; ++l) r[l] = reinterpret_cast<const double*>(base + index[l]);
    D word;
    Pair(r[0], r[1], r[2], r[3], z0, &word);
    *bits = _mm256_castpd_si256(word);
  }
};

}  // namespace
}  // namespace volume_internal
}  // namespace surfreg

#include "registration/volume_cost/volume_kernel_body.h"

namespace surfreg {
namespace volume_internal {

void IntegrateCellsAvx2(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                        CellKernelOutput* out) {
  IntegrateCells<Avx2>(in, lo, hi, gradient, out);
}

}  // namespace volume_internal
}  // namespace surfreg

#endif

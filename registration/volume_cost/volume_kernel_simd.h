#pragma once
// Internal to the incremental volume cost (volume_cost.cc): the cell kernel
// (unweighted or weighted) vectorized across overlay cells, on AVX-512 (8
// cells per vector) or AVX2 + FMA (4), chosen at run time. Not a public
// interface; volume_cost.cc keeps the scalar kernel as the fallback. The
// kernel itself is volume_kernel_body.h, compiled once per instruction set
// (volume_kernel_avx512.cc, volume_kernel_avx2.cc); this header is what the
// rest of the library sees, and none of it needs those instruction sets.
#include <cstdint>

#include "measure/surface.h"
#include "registration/volume_cost/cell_kernel.h"
#include "registration/volume_cost/overlay_topology.h"

namespace surfreg {
namespace volume_internal {

struct Gradient2 {
  double gx = 0, gy = 0;
};

// A triangle as the vector kernels load it: one cache line per triangle
// (8 or 4 of them transpose into 8 vectors), instead of ~12 gathers.
struct alignas(64) TriangleRecord {
  double x[3], y[3];  // corners
  double gx, gy;      // ∇ of the facet
};
// The rest: F at corner 0; in `bits`, bit i (0..2) set when edge i's
// endpoints (kFirst[i], kSecond[i]) are in decreasing global index order,
// bit 3 when the triangle has a hull edge (B's moving boundary).
struct alignas(16) TriangleExtra {  // aligned: AVX2 loads it whole
  double z0;
  uint32_t bits;
  uint32_t unused;  // 0: the vector kernels read `bits` as 64 bits
};
enum : uint32_t { kHullBit = 8 };

// The record of triangle `v` (global vertex indices) with facet gradient g.
inline void MakeRecord(const Point2* xy, const double* z, const int32_t* v, double gx, double gy,
                       bool hull, TriangleRecord* r, TriangleExtra* e) {
  for (int k = 0; k < 3; ++k) r->x[k] = xy[v[k]].x, r->y[k] = xy[v[k]].y;
  r->gx = gx;
  r->gy = gy;
  e->z0 = z[v[0]];
  e->bits = (v[1] > v[2] ? 1u : 0u) | (v[2] > v[0] ? 2u : 0u) | (v[0] > v[1] ? 4u : 0u) |
            (hull ? kHullBit : 0u);
  e->unused = 0;
}

// The weight μ on an A triangle (linear there, fixed with the reference):
// μ at its corner 0 and ∇μ.
struct WeightPlane {  // trivial: its per-triangle array is filled by chunks, unzeroed
  double m0, gx, gy;
};

// The interior gradient per cell. A cell's sign parts P (s the sign of d on
// P, μ ≡ 1 without weights) add n × Σ s∫_P μ q to the rotation's sum and
// Σ s∫_P μ n to the translation's, with n = (−∇F̂_B', 1) and q the moved
// point less the motion's offset (pair_state.h): affine on T_B, q0 at its
// corner 0 and ∂q/∂x = (1, 0, gx), ∂q/∂y = (0, 1, gy) there. With
// W = Σ s∫_P μ and (X, Y) = Σ s∫_P μ(x − p0), the first is
// n × (W q0 + X ∂q/∂x + Y ∂q/∂y): from the B triangle's record and the cell's
// own sums, so the cells of any range of A's triangles add up on their own.
//
// Some cells' interior sums: n × Σ s∫μq (before the motion's −Mᵀ) and Σ s∫μ n.
struct InteriorSums {
  double rotation[3] = {0, 0, 0}, translation[3] = {0, 0, 0};
};

// Per bin (GradientBins), a chunk's interior sums (6 doubles each, as
// InteriorSums) and whether it got any.
struct InteriorBins {
  const int32_t* bin_of_b = nullptr;  // per moved B triangle
  double* sums = nullptr;
  uint8_t* used = nullptr;
};

// The topology as plain arrays (OverlayTopology::cells, begins, counts),
// for the same reason.
struct CellKernelInput {
  const TopologyCell* cells = nullptr;
  const int64_t* cell_begin = nullptr;  // per A triangle
  const int32_t* cell_count = nullptr;  // per A triangle
  const TriangleRecord* record_a = nullptr;  // per A triangle
  const TriangleExtra* extra_a = nullptr;
  const WeightPlane* weight_a = nullptr;     // per A triangle; null: μ ≡ 1
  const TriangleRecord* record_b = nullptr;  // per moved B triangle
  const TriangleExtra* extra_b = nullptr;
  double offset[3] = {0, 0, 0};  // the motion's: q = moved point − offset
  InteriorBins bins;             // sums == nullptr: no bins
  // Called for every cell of a hull B triangle (with `gradient` only), for
  // the scalar boundary term.
  void (*on_hull)(void* context, int32_t ta, int32_t tb, int num_corners) = nullptr;
  void* context = nullptr;
};

struct CellKernelOutput {
  double abs = 0, area = 0;
  int64_t cells = 0;
  InteriorSums interior;  // `gradient` only
};

enum class CellKernel { kScalar, kAvx2, kAvx512 };

// The kernel a choice runs on this CPU (align.h's CellKernelChoice): the
// one named if the CPU runs it, else the best it runs, with a warning (once
// per process).
CellKernel ResolveCellKernel(CellKernelChoice choice);
const char* CellKernelName(CellKernel kernel);

// ∫μ|d| and ∫μ over the cells of A's triangles [lo, hi), and, with
// `gradient`, their interior sums (and, with in.bins, each bin's), as the
// scalar kernel (μ ≡ 1 without in.weight_a), by the vector kernel `kernel`
// (not kScalar; one ResolveCellKernel may return).
void IntegrateCellsSimd(CellKernel kernel, const CellKernelInput& in, int32_t lo, int32_t hi,
                        bool gradient, CellKernelOutput* out);

// IntegrateCellsSimd per instruction set, compiled for it: only through
// IntegrateCellsSimd, which calls them after the CPU check.
void IntegrateCellsAvx512(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                          CellKernelOutput* out);
void IntegrateCellsAvx2(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                        CellKernelOutput* out);

}  // namespace volume_internal
}  // namespace surfreg

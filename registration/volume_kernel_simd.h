#pragma once
// Internal to the incremental volume cost (volume_cost.cc): the cell kernel
// (unweighted or weighted) vectorized across overlay cells (8 per AVX-512
// vector). Not a public interface; volume_cost.cc keeps the scalar kernel
// as the fallback.
#include <array>
#include <cstdint>

#include "measure/surface.h"
#include "registration/overlay_topology.h"

namespace surfreg {
namespace volume_internal {

struct Gradient2 {
  double gx = 0, gy = 0;
};

// A triangle as the vector kernel loads it: one cache line per triangle
// (8 of them transpose into 8 vectors), instead of ~12 gathers.
struct alignas(64) TriangleRecord {
  double x[3], y[3];  // corners
  double gx, gy;      // ∇ of the facet
};
// The rest: F at corner 0; in `bits`, bit i (0..2) set when edge i's
// endpoints (kFirst[i], kSecond[i]) are in decreasing global index order,
// bit 3 when the triangle has a hull edge (B's moving boundary).
struct TriangleExtra {
  double z0;
  uint32_t bits;
  uint32_t unused;
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
struct WeightPlane {
  double m0 = 0, gx = 0, gy = 0;
};

struct CellKernelInput {
  const OverlayTopology* topology = nullptr;
  const TriangleRecord* record_a = nullptr;  // per A triangle
  const TriangleExtra* extra_a = nullptr;
  const WeightPlane* weight_a = nullptr;     // per A triangle; null: μ ≡ 1
  const TriangleRecord* record_b = nullptr;  // per moved B triangle
  const TriangleExtra* extra_b = nullptr;
  // Called for every cell of a hull B triangle (with `gradient` only), for
  // the scalar boundary term.
  void (*on_hull)(void* context, int32_t ta, int32_t tb, int num_corners) = nullptr;
  void* context = nullptr;
};

struct CellKernelOutput {
  double abs = 0, area = 0;
  int64_t cells = 0;
};

// Whether this CPU runs the vector kernel (AVX-512 F/DQ/VL).
bool CellKernelAvailable();

// ∫μ|d| and ∫μ over the cells of A's triangles [lo, hi), and, with
// `gradient`, Σ s∫_P μ and Σ s∫_P μ(x − p0) per B triangle added to
// `moment` (as the scalar kernel; μ ≡ 1 without in.weight_a). Only when CellKernelAvailable().
void IntegrateCellsSimd(const CellKernelInput& in, int32_t lo, int32_t hi, bool gradient,
                        std::array<double, 3>* moment, CellKernelOutput* out);

}  // namespace volume_internal
}  // namespace surfreg

#pragma once
// The volume cost (docs/method.md, How a registration runs): ρd per unit overlap area,
//   f(θ) = ∫_Ω |F̂_B'(x) − F̂_A(x)| dx / |Ω|,  Ω = region(A) ∩ region(B'),
// evaluated exactly on the overlay of A's mesh and B's moved mesh, with its
// exact gradient:
//   ∇∫|d| = ∫_Ω sign(d) ∂_θF̂_B' dx + ∮_{∂Ω ∩ ∂B'} |d| V_n ds,
//   ∇|Ω|  = ∮_{∂Ω ∩ ∂B'} V_n ds,
// where ∂_θF̂_B' = n·u (the Eulerian derivative of the moving height at fixed
// xy: n = (−∇F̂_B', 1), u = ∂T/∂θ at the material point above x) is affine on
// each overlay cell, so its integrals over the positive and negative parts
// of a cell are exact (area × value at the part's centroid), and V_n = u·n_out
// is the outward speed of B's moving boundary (A's boundary is fixed), whose
// product with |d| is piecewise quadratic along each edge (Simpson is exact).
//
// Per-point weights μ (ReferenceSide::weight, linear on each A triangle and
// fixed to the reference): f = ∫_Ω μ|d| / ∫_Ω μ, with
//   ∇∫μ|d| = ∫_Ω μ sign(d) ∂_θF̂_B' dx + ∮_{∂Ω ∩ ∂B'} μ|d| V_n ds,
//   ∇∫μ    = ∮_{∂Ω ∩ ∂B'} μ V_n ds
// (μ does not depend on θ at a fixed xy, so no other term): the interior
// integrand is a product of two affine functions (exact from the part's
// second moment), the boundary ones are cubic along an edge (Simpson).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "measure/mask_region.h"
#include "measure/tasks.h"
#include "registration/volume_cost/cell_kernel.h"
#include "registration/pair_state.h"

namespace surfreg {

struct VolumeCostValue {
  double abs = 0;   // ∫_Ω μ|d|
  double area = 0;  // ∫_Ω μ (|Ω| when μ = 1)
  Eigen::Matrix<double, 6, 1> d_abs = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> d_area = Eigen::Matrix<double, 6, 1>::Zero();
  int64_t cells = 0;

  double PerArea() const { return area > 0 ? abs / area : 0.0; }
  Eigen::Matrix<double, 6, 1> PerAreaGradient() const {
    return area > 0 ? Eigen::Matrix<double, 6, 1>((d_abs - PerArea() * d_area) / area)
                    : Eigen::Matrix<double, 6, 1>::Zero();
  }
};

// At the state's current θ (state.Update must have succeeded). On the
// threads `execution` allows, in chunks of A's triangles (the same bits on
// any number: measure/tasks.h). With `mask` (a region in A's frame, measure/mask_region.h), μ = 1
// on it and 0 elsewhere: both
// integrals and the area are taken over Ω ∩ mask, whose boundary moves only
// where it is B's (the mask is fixed to the reference). If the reference
// side has weights, μ is them (times the mask, if both are given).
VolumeCostValue EvaluateVolumeCost(const PairState& state, bool gradient, const Execution& execution,
                                   const MaskRegion* mask = nullptr);

// The gradient's shares over an n × n grid of square bins (the sandwich's
// tiles, registration/sandwich.h): each moved B triangle's part of ∇∫μ|d|
// and of ∇∫μ (its cells' interior and boundary terms) goes to the bin that
// holds its centroid. VolumeCostCache::Evaluate fills d_abs, d_area and used.
struct GradientBins {
  double x0 = 0, y0 = 0, side = 1;  // bin (i, j) covers x0 + [i, i + 1) side, y0 + [j, j + 1) side
  int n = 0;                        // outer bins take whatever lies beyond
  std::vector<Eigen::Matrix<double, 6, 1>> d_abs, d_area;  // n × n, row-major (j n + i)
  std::vector<uint8_t> used;                               // 1: some B triangle added to it
  int Index(double x, double y) const;
};

// What a VolumeCostCache did, summed over its evaluations.
struct VolumeCostCacheStats {
  int64_t evaluations = 0;
  int64_t full_builds = 0;         // evaluations that built the whole overlay
  int64_t fallbacks = 0;           // evaluations by the plain full path (too far to repair)
  int64_t triangles_searched = 0;  // A triangles searched again by repairs (builds not counted)
  int64_t triangles = 0;           // A triangles, summed over the evaluations
  int64_t cells = 0;               // cells integrated, summed over the evaluations
};

// EvaluateVolumeCost for a sequence of nearby θ of one PairState (a
// solver's evaluations), keeping the overlay's combinatorics between calls
// (registration/volume_cost/overlay_topology.h): each call re-searches only the A
// triangles near vertices whose location in the other mesh changed since the
// previous call, and integrates every cell from corners recomputed at the
// current points. The overlay is built whole on the first call, after B is
// re-triangulated (a fold), and for another state. When more than
// `max_dirty_fraction` of A's triangles would be searched again, the call is
// EvaluateVolumeCost's (never slower than it) and the overlay is kept for
// the pose it was made at (a solver often returns near it); when the next
// call is at another pose and again too far, it is built whole. Same value
// and gradient as EvaluateVolumeCost up to rounding (≈1e-13 relative); by
// fixed chunks of A's triangles added in order, so the same bits on any
// number of threads. Unmasked
// cells are integrated by a vector kernel on CPUs with AVX-512 or AVX2 +
// FMA (run-time check), or the one `kernel` names, for comparison and tests
// (one the CPU cannot run: a warning and the best it can).
//
// Keeps no reference to the state between calls, but remembers its address:
// call Reset() before using it with a new state at the same address whose B
// mesh differs from the last one seen (e.g. another level of the same pair).
class VolumeCostCache {
 public:
  explicit VolumeCostCache(double max_dirty_fraction = 0.25,
                           CellKernelChoice kernel = CellKernelChoice::kBest);
  ~VolumeCostCache();
  VolumeCostCache(const VolumeCostCache&) = delete;
  VolumeCostCache& operator=(const VolumeCostCache&) = delete;

  // As EvaluateVolumeCost (state.Update must have succeeded). With `bins`
  // (and `gradient`, no mask; else they are left empty), the gradient's
  // shares too, at no extra pass over the cells.
  VolumeCostValue Evaluate(const PairState& state, bool gradient, const Execution& execution,
                           const MaskRegion* mask = nullptr, GradientBins* bins = nullptr);
  // InteriorVolumeHessian (registration/volume_cost/volume_hessian.h) without a mask,
  // from the overlay the last Evaluate kept: call it right after an
  // unmasked Evaluate of `state` at its current θ.
  Eigen::Matrix<double, 6, 6> InteriorHessian(const PairState& state, const Execution& execution) const;
  void Reset();  // the next Evaluate builds the whole overlay
  const VolumeCostCacheStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfreg

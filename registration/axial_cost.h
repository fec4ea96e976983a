#pragma once
// The axial cost (ρ'd as least squares, docs/method.md, How a registration runs): one residual per node
// inside the overlap, with analytic Jacobians,
//   node i of A located in B':  r = F̂_B'(x_i, y_i) − z_i,
//   node j of B (moved):        r = F̂_A(x'_j, y'_j) − z'_j.
// For a unit-free direction n = (−∂F/∂x, −∂F/∂y, 1) of the surface that is
// interpolated, dr/dt = ±n and dr/dω = ∓Mᵀ(n × q) (rigid_motion.h), q the
// moved material point relative to c + t; for A's nodes the material point
// is the barycentric combination of the moved B triangle's corners (the
// Eulerian derivative of the moving height at fixed xy).
//
// Per-point weights μ (ReferenceSide::weight, linear on A's mesh, fixed to
// the reference): node k's residual is multiplied by sqrt(μ_k), so the sum of
// squares is Σ μ_k r_k². A's μ_i is a constant; B's μ_j = μ(x'_j) follows the
// moved node through A's mesh, and its derivative is part of the Jacobian:
//   d(sqrt(μ) r) = sqrt(μ) dr + r dμ / (2 sqrt(μ)),
//   dμ/dt = g, dμ/dω = −Mᵀ(g × q),  g = (∂μ/∂x, ∂μ/∂y, 0) on the A triangle.
// Nodes with μ = 0 are inactive. The second term grows like 1/sqrt(μ) as a
// node approaches a zero-weight triangle (sqrt(μ) r has an infinite slope
// there; μ r², the cost, does not): the gradient Jᵀr stays exact and
// bounded, only the Gauss-Newton matrix is inflated for those few nodes.
// Trimming and a robust loss see the weighted residuals sqrt(μ) r.
//
// The taper τ: every residual is multiplied by τ, the other surface's
// inner-vertex flags (measure/domain.h InteriorVertices) interpolated where
// the node lies, 1 except on the outer ring of triangles of that surface's
// data (B's: its active triangles), where it falls linearly to 0 at the
// outline. A node entering or leaving Ω then changes the cost continuously
// instead of by its whole r² (which made trust-region steps alternate between
// two costs). Its derivative, r ∇τ moved as μ's, is in the Jacobian, and the
// normalization below counts Σ μ τ².
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "measure/mask_region.h"
#include "measure/uninitialized_vector.h"
#include "registration/pair_state.h"

namespace surfreg {

struct AxialResiduals {
  // Indexed by node: A's nodes first, then B's. Inactive nodes (outside the
  // overlap, outside the mask, μ = 0, or trimmed) have r = 0 and a zero
  // Jacobian. With weights, r and the Jacobian are the weighted ones.
  // (Set by chunks on the evaluation's threads.)
  UninitializedVector<double> r;
  UninitializedVector<std::array<double, 6>> jacobian;  // d r / d(rx, ry, rz, tx, ty, tz)
  UninitializedVector<uint8_t> active;
  int64_t active_count = 0;
  double active_weight = 0;   // Σ μ over the active nodes (= active_count without weights)
  int64_t overlap_count = 0;  // nodes inside the overlap (before trimming and mask)
  double trim_threshold = 0;  // |r| above which nodes were trimmed (0: none)
  // The evaluation's scratch (each node's share of the normalization, μ τ²,
  // and its derivative), kept here so that the next evaluation reuses its
  // memory instead of faulting in fresh pages (384 MB of derivatives for two
  // 2000² DEMs' 8e6 nodes).
  UninitializedVector<double> node_weight;
  UninitializedVector<std::array<double, 6>> d_weight;
};

struct AxialSettings {
  double trim_fraction = 0.0;  // drop this fraction of the largest |r| (0 ≤ f < 0.5)
  // μ as a mask in A's local frame (null: μ = 1); shared with the volume
  // cost (SolveContext) and every level, as it is built once.
  std::shared_ptr<const MaskRegion> mask;
  // If > 0, residuals are scaled by sqrt(normalize_count / active_weight),
  // so the sum of squares is a (weighted) mean over the overlap: otherwise
  // sliding the surfaces apart lowers the cost by dropping nodes (partial
  // overlap). With weights, active_weight depends on θ through B's μ_j and
  // the Jacobian includes the derivative of the scale.
  double normalize_count = 0;
  // Multiply each residual by w_k, the cos of the other surface's slope at
  // node k: the vertical gap becomes about the gap along the normal
  // (point-to-plane). Steep walls, where two samplings of one surface differ
  // by large vertical gaps for a tiny sideways offset, then neither dominate
  // nor bias the fit. w is linear on each triangle, from its corners' unit
  // vertex normals (PairState::reference_cosine, moving_normal): a
  // triangle's own slope would make the cost jump wherever a node crosses an
  // edge, and Levenberg-Marquardt then alternates between two costs. Applied
  // before trimming, μ and the normalization; its derivative (B's normals
  // turn with ω, and w moves with the node) is in the Jacobian.
  bool normal_distance = false;
  // Which surfaces' nodes give residuals: both (ρ'd), or only one, e.g. the
  // sparser one's samples against the denser interpolation
  // (CostKind::kAxialSparser).
  bool reference_nodes = true;
  bool moving_nodes = true;
};

// Residuals (and Jacobians if `jacobians`) at the state's current θ.
void ComputeAxialResiduals(const PairState& state, const AxialSettings& settings, bool jacobians,
                           AxialResiduals* out);

}  // namespace surfreg

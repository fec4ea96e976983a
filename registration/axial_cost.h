#pragma once
// The axial cost (ρ'd as least squares, DESIGN.md 4): one residual per node
// inside the overlap, with analytic Jacobians,
//   node i of A located in B':  r = F̂_B'(x_i, y_i) − z_i,
//   node j of B (moved):        r = F̂_A(x'_j, y'_j) − z'_j.
// For a unit-free direction n = (−∂F/∂x, −∂F/∂y, 1) of the surface that is
// interpolated, dr/dt = ±n and dr/dω = ∓Mᵀ(n × q) (rigid_motion.h), q the
// moved material point relative to c + t; for A's nodes the material point
// is the barycentric combination of the moved B triangle's corners (the
// Eulerian derivative of the moving height at fixed xy).
#include <array>
#include <cstdint>
#include <vector>

#include "registration/pair_state.h"

namespace surfreg {

struct AxialResiduals {
  // Indexed by node: A's nodes first, then B's. Inactive nodes (outside the
  // overlap, outside the mask, or trimmed) have r = 0 and a zero Jacobian.
  std::vector<double> r;
  std::vector<std::array<double, 6>> jacobian;  // d r / d(rx, ry, rz, tx, ty, tz)
  std::vector<uint8_t> active;
  int64_t active_count = 0;
  int64_t overlap_count = 0;  // nodes inside the overlap (before trimming and mask)
  double trim_threshold = 0;  // |r| above which nodes were trimmed (0: none)
};

struct AxialSettings {
  double trim_fraction = 0.0;  // drop this fraction of the largest |r| (0 ≤ f < 0.5)
  // μ as a mask: a simple polygon in A's local frame (empty: μ = 1).
  std::vector<Point2> mask;
  // If > 0, residuals are scaled by sqrt(normalize_count / active nodes), so
  // the sum of squares is a mean over the overlap: otherwise sliding the
  // surfaces apart lowers the cost by dropping nodes (partial overlap).
  double normalize_count = 0;
};

// Residuals (and Jacobians if `jacobians`) at the state's current θ.
void ComputeAxialResiduals(const PairState& state, const AxialSettings& settings, bool jacobians,
                           AxialResiduals* out);

}  // namespace surfreg

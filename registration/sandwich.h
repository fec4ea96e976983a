#pragma once
// The motion's covariance for the volume cost actually minimized: a
// sandwich (Huber–White) estimate clustered over tiles of the overlap,
//   C = H⁻¹ M H⁻¹,
// with H the curvature of the per-area cost f(θ) at the solution (its line
// integral along the gap's zero set and its kinks along B's edges,
// registration/volume_cost/volume_hessian.h: what governs the estimate as the density
// of residuals at 0 does an L1 regression's), and M the spread of the
// gradient's contributions of the B tiles, Σ_b (s_b − s̄)(s_b − s̄)ᵀ · B / (B − p)
// for p free parameters (the fit made the scores sum to zero along p
// directions: HC1's small-sample factor, calibrated by
// tests/stddev_calibration_test.cc and the peer pairs). Whole tiles, not cells,
// so that residuals correlated within a tile (a shared triangle's error,
// a sampling pattern) count as they do; the information estimate sees
// neither the L1 cost nor that correlation.
#include <array>

#include <Eigen/Core>

#include "registration/axial_cost.h"
#include "registration/pair_state.h"
#include "registration/solvers.h"

namespace surfreg {

// About this many tiles hold overlap (squares of side √(|Ω| / count)):
// one per kSandwichNodesPerTile nodes of the smaller cloud (tiles about 10
// sample spacings wide, several times the reach of one triangle's error,
// which the tiles must hold), at least kSandwichTiles (the meat of fewer,
// heavy-tailed scores, a few building edges, is itself too noisy: 4.4% of
// the LIDAR pairs' errors beyond 3σ with 64 tiles, 2.2% with 128 to 512),
// at most kMaxSandwichTiles.
inline constexpr int kSandwichTiles = 64;
inline constexpr int kSandwichNodesPerTile = 100;
inline constexpr int kMaxSandwichTiles = 1024;
int SandwichTileCount(std::size_t smaller_cloud_nodes);

struct SandwichEstimate {
  bool ok = false;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // θ order; locked rows 0
  int tiles = 0;  // tiles that held overlap
};

// At the state's θ (state.Update must have succeeded). Not ok with fewer tiles than 2 × free parameters, or an H that
// is not positive definite (then the caller keeps the information
// estimate). `cache`: an overlay cache bound to `state` (the volume
// solve's, at its solution), else a new one.
SandwichEstimate SandwichCovariance(const PairState& state, const SolveContext& context,
                                    VolumeCostCache* cache = nullptr);

// The meat of the axial cost's sandwich from residuals computed at the
// state's θ (with Jacobians): the active nodes' shares r_k J_kᵀ of Jᵀr,
// summed over the tiles AxialSandwichCovariance uses (A's nodes, then B's
// moved ones, binned where they lie; about SandwichTileCount tiles), and
// their spread Σ_b (s_b − s̄)(s_b − s̄)ᵀ · B / (B − p), p the free parameters.
// `tiles`: the tiles that held an active node.
Eigen::Matrix<double, 6, 6> AxialScoreSpread(const PairState& state, const AxialResiduals& residuals,
                                             int free_parameters, int* tiles);

// The same for the axial cost at the state's θ: H by central differences
// of Jᵀr, M the spread of the tiles' shares of Jᵀr (nodes binned where
// they lie).
SandwichEstimate AxialSandwichCovariance(PairState& state, const SolveContext& context,
                                         const std::array<double, 6>& step);

}  // namespace surfreg

#pragma once
// One solve of the registration at one level from one start, with Ceres
// (internal to align.cc; docs/method.md, How a registration runs).
// - axial: ceres::Problem, one residual block per node (so a robust loss
//   applies per node), all blocks served from one evaluation of the state per
//   new θ (ceres::EvaluationCallback), trust region.
// - volume: ceres::GradientProblem over ρd per unit overlap area, line search.
// Only the free parameters are optimized; rotations are scaled by a length
// (the moving cloud's RMS radius) so that all parameters are lengths, which
// keeps trust regions well scaled; the line search runs in coordinates that
// whiten the volume cost's curvature at its start (registration/volume_cost/volume_hessian.h;
// the axial cost's under a mask).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "registration/align_options.h"
#include "registration/axial_cost.h"
#include "registration/pair_state.h"
#include "registration/volume_cost/volume_cost.h"

namespace surfreg {

// Threads for a Ceres solve: `requested` as ExecutionFor reads it (0: every
// core), at most the cores (Ceres bounds more itself, with a warning per
// solve). For problems of one residual block only: Ceres adds several
// blocks' costs per thread, so the sum's last bits depend on the count.
int CeresThreads(int requested);

struct SolveContext {
  const AlignOptions* options = nullptr;
  // What the alignment solves, resolved once from the options and the data
  // (align_steps::MakeContext, CheckStart; the options are never written):
  // the cost (the options', or the axial cost at the sparser surface's
  // nodes for terrain of two resolutions), and the axial loss's scale
  // (> 0: measured at the start; else the options' loss_scale).
  CostKind solve_cost = CostKind::kVolume;
  bool sparser_nodes = false;  // the axial residuals at the sparser surface's nodes only
  double loss_scale = 0;
  AxialSettings axial;
  double rotation_scale = 1.0;  // length that multiplies radians
  int level = 0, start = 0;
  const char* cost = "axial";  // for the log
  double seconds_offset = 0;    // time already spent, for the log
  std::vector<AlignOptions::Iteration>* log = nullptr;
  // SolveAxial as the volume cost's prealignment: it only has to land in the
  // volume cost's basin, so it stops at a coarser tolerance
  // (kPrealignTolerance) than the final solve's.
  bool prealignment = false;
};

// The volume solve's overlay cache repairs its topology while at most this
// share of A's triangles must be searched again (VolumeCostCache): the
// whitened line search's first trials go far, and repairing them cost fewer
// instructions than the plain evaluation at 0.25 (whole `surfreg align`,
// callgrind: a clean face pair −5%, a clean LIDAR pair −6%, three others
// unchanged; 1.0 gave the same as 0.5).
inline constexpr double kSolveDirtyFraction = 0.5;

// Relative cost decrease and relative step below which the prealignment stops.
inline constexpr double kPrealignTolerance = 1e-7;

struct SolveResult {
  std::array<double, 6> theta{};
  double initial_cost = 0, final_cost = 0;  // the solver's objective
  int iterations = 0;
  bool converged = false;  // the solver met a convergence tolerance
  bool usable = false;     // the solution is finite and evaluable
  int rounds = 0;  // volume: solves, B re-triangulated between them (stopped against a fold); axial: 1
  std::string message;
  // Volume, when asked (VolumeWhitening::want_final): the cost's curvature
  // at the solution (per unit area, all six parameters); zero otherwise.
  Eigen::Matrix<double, 6, 6> curvature = Eigen::Matrix<double, 6, 6>::Zero();
};

// How a volume solve is whitened: by default by the cost's own curvature at
// its start (a pass over the overlay that costs about five evaluations);
// `given`: by this one instead (per unit area, all six parameters), e.g.
// what a solve on a subsample of the same pair returned at the point this
// one starts from. `given_cost`: the per-area cost where `given` was taken
// (> 0: `given` is rescaled by given_cost / this solve's cost at its start,
// as an L1 cost's curvature goes as 1 / the gaps' scale, which a finer
// sampling shrinks). `want_final`: return the curvature at the solution.
struct VolumeWhitening {
  const Eigen::Matrix<double, 6, 6>* given = nullptr;
  double given_cost = 0;
  bool want_final = false;
};

// Scale of the robust loss at the state's current θ: 3 × 1.4826 × median
// |residual| over the active nodes (a robust σ, times 3), or `floor` if that is 0.
double AutomaticLossScale(const PairState& state, const AxialSettings& settings, double floor);

SolveResult SolveAxial(PairState& state, const SolveContext& context,
                       const std::array<double, 6>& theta0);
// With `keep`, the solve evaluates through that overlay cache and leaves
// B's surface fixed as it ended (`keep` stays bound to `state`): what is
// evaluated at the solution next (the sandwich σ) repairs the overlay
// instead of building it again, which costs several evaluations.
SolveResult SolveVolume(PairState& state, const SolveContext& context,
                        const std::array<double, 6>& theta0, VolumeCostCache* keep = nullptr,
                        const VolumeWhitening& whitening = VolumeWhitening());

struct Information {
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  bool covariance_ok = false;
  std::array<double, 6> observability{};
  std::array<bool, 6> constrained{};
  double condition_number = 0;
};

// Observability from JᵀJ of the axial residuals at the state's θ, and (if
// `covariance`) the parameter covariance from ceres::Covariance scaled by the
// residual variance. Locked parameters get 0 and count as constrained.
Information AnalyseInformation(PairState& state, const SolveContext& context, bool covariance);

}  // namespace surfreg

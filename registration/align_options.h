#pragma once
// What Align is asked to do (registration/align.h): the cost, the solvers'
// options, the levels and starts, the weights and mask, the stable terrain,
// the assessments, and the callbacks for progress. Plain data: Align reads
// the options and never changes them.
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <ceres/gradient_problem_solver.h>
#include <ceres/solver.h>

#include "measure/measures.h"
#include "measure/surface.h"
#include "registration/rigid_motion.h"
#include "registration/stable_terrain.h"
#include "registration/volume_cost/cell_kernel.h"

namespace surfreg {

// The cost the solve minimizes (AlignOptions::cost).
//   kAuto: the volume cost, except for terrain of two resolutions (one
//     surface has at least kSparserNodesRatio times the other's area per
//     sample and its curvature changes sign from place to place), which is
//     solved as kAxialSparser. Terrain sampled 3 : 1: errors 0.78 × / 0.76 ×
//     the volume cost's, 4 : 1: 0.63 × / 0.64 ×; 2 : 1: 1.11 × / 1.17 ×
//     (docs/registration.md), hence 2.5 between.
//   kVolume: ρd per unit overlap area, whatever the data.
//   kAxial: least squares on the vertical gaps at both surfaces' nodes (ρ'd).
//   kAxialSparser: the axial cost at the sparser surface's nodes only (by
//     area per sample), each against the denser interpolation, with no slope
//     or gap weight: for DEMs or clouds of different resolutions, where the
//     sparser interpolation's own error would fill the cost. Not for faces,
//     where the vertical gaps on steep flanks make it worse.
// An explicit choice is always solved as given.
enum class CostKind { kAuto, kVolume, kAxial, kAxialSparser };
inline constexpr double kSparserNodesRatio = 2.5;
enum class LossKind { kNone, kHuber, kSoftL1, kCauchy };

// The Ceres options Align starts from (AlignOptions::axial_solver and
// volume_solver): Levenberg–Marquardt with dense QR (the most stable; dense
// normal Cholesky is faster but squares the condition number; CGNR is
// iterative and inexact), and L-BFGS; 100 iterations per level and start;
// a function tolerance of 1e-12; parameter tolerances of 1e-10 (trust
// region) and 1e-14 (line search) of the parameters' size, far below any
// accuracy the data support; no gradient tolerance (1e-16); silent.
ceres::Solver::Options DefaultAxialSolverOptions();
ceres::GradientProblemSolver::Options DefaultVolumeSolverOptions();

// Parameter order everywhere: rx, ry, rz (rotation vector, radians), tx, ty, tz.
inline constexpr std::array<const char*, 6> kParameterNames = {"rx", "ry", "rz", "tx", "ty", "tz"};

struct AlignOptions {
  // The volume cost is the default's: on two different samplings of one
  // surface its minimum lies closer to the true motion than the axial
  // cost's (measured: tests/align_test.cc, docs/registration.md).
  CostKind cost = CostKind::kAuto;
  // Volume cost: first solve with the axial cost (trust region, fast and
  // with a wide basin) on the coarsest level, subsampled to at most about
  // 5000 points of each surface (it only has to land in the volume cost's
  // basin), then refine with the volume cost.
  bool prealign = true;
  LossKind loss = LossKind::kNone;
  // Scale of the robust loss in data units (residuals beyond it are
  // down-weighted); 0 = automatic: 3 × 1.4826 × median |residual| at the
  // initial motion.
  double loss_scale = 0.0;
  // The solvers, configured as Ceres documents them: axial_solver (a trust
  // region) for the axial cost and the prealignment, volume_solver (a line
  // search) for the volume cost; each run of a level and start takes them
  // as they are, adding its own callbacks (their callbacks run too), the
  // thread count of num_threads, and for the volume solver
  // update_state_every_iteration; the prealignment stops at a relative
  // tolerance of at least 1e-6. IsValid checks them with Ceres' IsValid.
  ceres::Solver::Options axial_solver = DefaultAxialSolverOptions();
  ceres::GradientProblemSolver::Options volume_solver = DefaultVolumeSolverOptions();
  CellKernelChoice cell_kernel = CellKernelChoice::kBest;
  // Drop this fraction (0 ≤ f < 0.5) of the worst residuals at each
  // evaluation: for partial overlap and regions that really changed. Axial
  // cost only.
  double trim_fraction = 0.0;
  // Axial cost and prealignment: weight each vertical gap by the cosine of
  // the surface's slope there, i.e. ≈ the distance along the normal. Steep
  // flanks (face sides, cliffs) otherwise dominate least squares with
  // vertical gaps that interpolation error inflates.
  bool normal_distance = true;
  // Volume cost (and its prealignment): μ times cos(slope of the reference
  // at each node)^slope_weight (pair_state.h ApplySlopeWeight); 0 = off.
  // The reported measures stay unweighted.
  double slope_weight = 1.0;
  // Volume cost (and its prealignment): μ also times f / (f + g), g the
  // reference's local curvature as an interpolation gap and f = gap_weight
  // × its median (gap_weight.h ApplyGapWeight); 0 = off. Clean faces' errors
  // are several times smaller with it (docs/registration.md).
  double gap_weight = 0.3;
  // Volume cost (and its prealignment): where the reference's local area
  // per sample varies by this ratio or more (its 90th over its 10th
  // percentile: a mesh's vertices), μ also times the median area per sample
  // over the local one, so that each sample counts alike (gap_weight.h
  // ApplyDensityWeight); 0 = off. Random samplings give 2.5-2.6.
  double density_weight = 5.0;
  // When one surface has this many times the other's area per sample or
  // more, the sparser one's nodes are lowered by the difference of the two
  // samplings' mean chord at their curvature (chord_bias.h
  // CorrectDensityBias; only on a surface curved mostly one way); 0 = off.
  // Clean faces sampled 4 : 1: translation errors 5-8 × smaller
  // (docs/registration.md). The reported measures stay on the data as sampled.
  double density_correction = 1.2;
  // Which of rx, ry, rz, tx, ty, tz the solver may change; the others keep
  // their initial value.
  std::array<bool, 6> free = {true, true, true, true, true, true};
  // Coarse-to-fine: `levels` ≥ 1 solves, the first on both clouds subsampled
  // by level_factor^(levels−1), each starting where the previous ended.
  int levels = 1;
  double level_factor = 4.0;
  // Fraction in (0, 1] of each cloud's points (a fixed pseudo-random subset)
  // solved on at the finest level; coarser levels keep subsample ×
  // level_factor^−k of them. The centre stays the full moving cloud's
  // centroid, and the measures before and after use all points.
  double subsample = 1.0;
  // Multi-start: besides the initial guess, this many starts perturbed by
  // ±multi_start_angle_deg about each axis and ±multi_start_shift (data
  // units) along each axis (deterministic pattern); the lowest final cost wins.
  int multi_start = 0;
  double multi_start_angle_deg = 2.0;
  double multi_start_shift = 0.0;  // 0 = 5 mean sample spacings
  // A wider search before the solve (registration/wide_search.h): 50 starts
  // (the initial motion turned by 12° and 24° about 12 axes, each with its
  // translation and with the centroids matched) solved with the axial cost
  // on a subsample of about 2000 points each; the solve starts from the
  // best. For starts beyond the prealignment's basin (about 10° and 20
  // sample spacings). It costs 1–3 s (measured on the benchmark's pairs), so
  // kAuto runs it only when the alignment from the initial motion fails or
  // does not improve the measure, and keeps what it finds if that converges
  // and improves.
  enum class WideSearch { kNever, kAuto, kAlways };
  WideSearch wide_search = WideSearch::kAuto;
  // The start: either a motion in input coordinates (a transform another
  // tool produced, or an earlier result), or a rotation vector (radians)
  // about the moving surface's centroid and that centroid's shift (data
  // units); not both.
  std::optional<Rigid3d> initial_reference_from_moving;
  std::array<double, 3> initial_rotation = {0, 0, 0};
  std::array<double, 3> initial_translation = {0, 0, 0};
  // The weight μ used by the cost and the reported measures, as in
  // MeasureOptions: uniform; a mask (rings in input coordinates, even–odd,
  // include or exclude); or per
  // point: the REFERENCE's per-sample weights (Surface::weight, required),
  // linear on its mesh and fixed with it (carried to every level and
  // subsample). The axial cost weights node k's squared residual by μ_k
  // (B's nodes by μ where they land), the volume cost is ∫μ|d| / ∫μ.
  WeightMode weight = WeightMode::kUniform;
  // AlignResult::before and ::after keep the node gaps
  // (MeasureOptions::keep_node_gaps: d at every sample of each surface, and
  // the reference's node areas), e.g. for a DoD on the reference's nodes.
  bool keep_node_gaps = false;
  std::vector<MaskRing> mask;
  MaskMode mask_mode = MaskMode::kInclude;
  // Stable terrain (registration/stable_terrain.h): with kAuto (the
  // default) Align fits, classifies the reference's samples into stable and
  // changed by their gaps, fits again on the stable ones, until the set
  // settles; then solves once more from the start on that set, so the
  // result (verdict, σ) is that of an alignment on the stable terrain. The
  // user's μ still applies: the stable set is inside it (a mask becomes its
  // samples' membership, per point). AlignResult::stable says what was left
  // out. kAll: the whole overlap (under μ).
  StableOptions stable;
  // Moving triangles that turn over in projection under a tilt: up to this
  // share of the moving surface's area they are slivers standing nearly
  // vertical, and the moving surface is re-triangulated at that pose
  // (counted in AlignResult::remeshes); beyond it the surface overlaps
  // itself in xy, which the solver treats as an infeasible step.
  double max_fold_fraction = 0.5;
  // Which triangles of each surface are data (measure/domain.h); the cost
  // and the reported measures integrate over the two domains' intersection.
  DomainRule domain;
  // A held-out check (registration/holdout.h): fit on the reference less a
  // seeded random share `holdout_fraction` of its tiles, then report dz on
  // those tiles before and after (AlignResult::holdout). 0 = off: the fit
  // uses everything. With `holdout_verdict`, an alignment that does not
  // improve the held-out part (its robust RMSE) is not converged_improved.
  double holdout_fraction = 0.0;
  uint64_t holdout_seed = 1;
  bool holdout_verdict = false;
  // Standard deviations from subsamples: this many alignments, each on the
  // reference less a seeded random half of its 8 × 8 tiles, started at the
  // full solution; σ² of each parameter is the mean squared difference of
  // their motions from the full one (for half samples that difference has
  // about the full estimate's variance). Blocks of the surface, not points,
  // so that spatially correlated errors count as they do. 0 = the
  // information estimate (the axial residuals' σ² (JᵀJ)⁻¹).
  int stddev_subsamples = 0;
  // Without subsamples: the volume cost's σ from a sandwich estimate
  // (registration/sandwich.h: the cost's Hessian around the motion's own
  // uncertainty, and the spread of the gradient over ~64 tiles of the
  // overlap); or, and always for the axial cost, from the information (the
  // axial residuals' σ² (JᵀJ)⁻¹), which sees neither the L1 cost nor
  // spatially correlated residuals.
  enum class StddevMethod { kSandwich, kInformation };
  StddevMethod stddev_method = StddevMethod::kSandwich;
  bool compute_covariance = true;
  int num_threads = 0;  // 0: every core (measure/tasks.h, ExecutionFor)
  // Called after every solver iteration (progress, logs).
  struct Iteration {
    int level = 0;      // 0 = coarsest
    int start = 0;      // multi-start index
    const char* cost_name = "axial";  // the cost being minimized: "axial" (also the prealignment) or "volume"
    int iteration = 0;
    double cost = 0;    // the solver's objective
    double step_norm = 0;
    double gradient_norm = 0;
    double seconds = 0;  // since the start of this solve (a wide search or a stable-terrain round starts again)
  };
  std::function<void(const Iteration&)> on_iteration;
  // Called (from Align's thread) as a long stage begins: "solving" once both
  // surfaces are prepared, "measuring the result" after the solve, "wide
  // search ..." when the first solve's verdict calls for one, with the
  // seconds since the start of that solve.
  std::function<void(const char* stage, double seconds)> on_stage;

  bool IsValid(std::string* error) const;
};

}  // namespace surfreg

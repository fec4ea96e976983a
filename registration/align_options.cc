// AlignOptions' checks and the small public helpers of align.h (verdict
// names, Euler angles, moving a surface by a matrix): kept apart from the
// alignment pipeline in align.cc.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "measure/tasks.h"
#include "registration/align.h"

namespace surfreg {

namespace {

// What both solvers stop on: 100 iterations per level and start, a relative
// cost decrease of 1e-12 (the volume solver's: below), no gradient
// tolerance; silent.
template <typename CeresOptions>
CeresOptions WithAlignStops(CeresOptions o, double parameter_tolerance) {
  o.max_num_iterations = 100;
  o.function_tolerance = 1e-12;
  o.gradient_tolerance = 1e-16;
  o.parameter_tolerance = parameter_tolerance;
  o.logging_type = ceres::SILENT;
  return o;
}

}  // namespace

ceres::Solver::Options DefaultAxialSolverOptions() {
  ceres::Solver::Options o;
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_QR;
  return WithAlignStops(o, 1e-10);
}

ceres::GradientProblemSolver::Options DefaultVolumeSolverOptions() {
  ceres::GradientProblemSolver::Options o;
  o.line_search_direction_type = ceres::LBFGS;
  // The start's curvature (the whitening, solvers.cc) underestimates the
  // curvature near the minimum, where the gap's zero line is longest: the
  // unit step overshot and every line search took two evaluations. Scaled
  // by sᵀy / yᵀy each iteration, the step fits the curvature met so far:
  // 17 → 13 evaluations at 1e5 points, 3% fewer on the 120 peer pairs.
  o.use_approximate_eigenvalue_bfgs_scaling = true;
  o = WithAlignStops(o, 1e-14);
  // Near the minimum a change of the motion by 1% of its standard deviation
  // changes the cost by about 1e-4 / N relatively (N nodes), more than this
  // on any cloud up to 1e5 points: the last iterations below it moved the
  // motion by far less than its uncertainty (15% of the volume evaluations
  // on ten peer pairs; the 120 pairs' error ratios to ICP unchanged).
  o.function_tolerance = 1e-9;
  return o;
}

bool AlignOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    *error = message;
    return false;
  };
  if (!(loss_scale >= 0) || !std::isfinite(loss_scale)) return fail("loss_scale must be >= 0");
  if (axial_solver.max_num_iterations < 1 || volume_solver.max_num_iterations < 1) {
    return fail("max_iterations must be >= 1");
  }
  for (const double tolerance : {axial_solver.function_tolerance, volume_solver.function_tolerance}) {
    if (!(tolerance > 0 && tolerance < 1)) return fail("function_tolerance must be in (0, 1)");
  }
  if (axial_solver.minimizer_type != ceres::TRUST_REGION) return fail("axial_solver: the minimizer must be a trust region");
  if (!(trim_fraction >= 0 && trim_fraction < 0.5)) return fail("trim_fraction must be in [0, 0.5)");
  if (std::none_of(free.begin(), free.end(), [](bool f) { return f; })) {
    return fail("free: at least one parameter must be free");
  }
  if (levels < 1 || levels > 8) return fail("levels must be in [1, 8]");
  if (!(level_factor >= 1.5 && level_factor <= 64)) return fail("level_factor must be in [1.5, 64]");
  if (!(subsample > 0 && subsample <= 1)) return fail("subsample must be in (0, 1]");
  if (axial_solver.linear_solver_type == ceres::CGNR && axial_solver.trust_region_strategy_type == ceres::DOGLEG) {
    return fail("linear_solver cgnr needs trust_region levenberg_marquardt (dogleg needs a factorization)");
  }
  std::string ceres_error;
  if (!axial_solver.IsValid(&ceres_error)) return fail("axial_solver: " + ceres_error);
  if (!volume_solver.IsValid(&ceres_error)) return fail("volume_solver: " + ceres_error);
  if (multi_start < 0 || multi_start > 1000) return fail("multi_start must be in [0, 1000]");
  if (!(multi_start_angle_deg >= 0 && multi_start_angle_deg <= 90)) {
    return fail("multi_start_angle_deg must be in [0, 90]");
  }
  if (!(multi_start_shift >= 0) || !std::isfinite(multi_start_shift)) return fail("multi_start_shift must be >= 0");
  if (!(max_fold_fraction >= 0 && max_fold_fraction <= 1)) return fail("max_fold_fraction must be in [0, 1]");
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(initial_rotation[k]) || !std::isfinite(initial_translation[k])) {
      return fail("initial motion must be finite");
    }
  }
  if (initial_reference_from_moving) {
    if (!IsRigid(initial_reference_from_moving->ToMatrix())) {
      return fail("initial_reference_from_moving must be a rigid motion (a rotation and a translation)");
    }
    for (int k = 0; k < 3; ++k) {
      if (initial_rotation[k] != 0 || initial_translation[k] != 0) {
        return fail("initial_reference_from_moving and initial_rotation/initial_translation both set the start");
      }
    }
  }
  if ((cost == CostKind::kVolume || cost == CostKind::kAuto) && trim_fraction > 0) {
    return fail("trim_fraction applies to cost axial or axial_sparser only");
  }
  if (num_threads < 0) return fail("threads must be >= 1 (0: every core)");
  if (!(slope_weight >= 0 && slope_weight <= 8)) return fail("slope_weight must be in [0, 8]");
  if (!(gap_weight >= 0 && gap_weight <= 100)) return fail("gap_weight must be in [0, 100]");
  if (!(density_correction == 0 || (density_correction >= 1 && density_correction <= 1e6)))
    return fail("density_correction must be 0 (off) or a ratio in [1, 1e6]");
  if (!(holdout_fraction >= 0 && holdout_fraction < 0.9)) return fail("holdout must be in [0, 0.9)");
  if (!(stable.grow_sigmas > 0 && stable.seed_sigmas >= stable.grow_sigmas && std::isfinite(stable.seed_sigmas))) {
    return fail("stable_sigmas must be finite and at least stable_grow_sigmas, which must be > 0");
  }
  if (stable.min_region_samples < 1 || stable.margin_rings < 0 || stable.max_rounds < 1) {
    return fail("stable terrain: min_region_samples and max_rounds must be >= 1, margin_rings >= 0");
  }
  if (stddev_subsamples < 0 || stddev_subsamples > 1000) return fail("stddev_subsamples must be in [0, 1000]");
  MeasureOptions m;
  m.weight = weight;
  m.mask = mask;
  m.mask_mode = mask_mode;
  return m.IsValid(error);
}

const char* VerdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kConvergedImproved: return "converged_improved";
    case Verdict::kConvergedNotImproved: return "converged_not_improved";
    case Verdict::kIllConditioned: return "ill_conditioned";
    case Verdict::kFailed: return "failed";
  }
  return "?";
}

std::array<double, 3> EulerDegrees(const Eigen::Matrix3d& r) {
  const double degrees = 180.0 / M_PI;
  const double ry = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  return {std::atan2(r(2, 1), r(2, 2)) * degrees, ry * degrees,
          std::atan2(r(1, 0), r(0, 0)) * degrees};
}

Surface TransformSurface(const Surface& surface, const Eigen::Matrix4d& matrix, int threads) {
  // Rotate local coordinates and move the origin separately: no large
  // coordinates are multiplied by the rotation.
  const Eigen::Matrix3d r = matrix.topLeftCorner<3, 3>();
  const Eigen::Vector3d origin(surface.origin[0], surface.origin[1], surface.origin[2]);
  const Eigen::Vector3d moved_origin = r * origin + matrix.topRightCorner<3, 1>();
  const auto moved_point = [&](std::size_t i) {
    const Eigen::Vector3d p = r * Eigen::Vector3d(surface.xy[i].x, surface.xy[i].y, surface.z[i]);
    return std::array<double, 3>{p.x() + moved_origin.x(), p.y() + moved_origin.y(), p.z() + moved_origin.z()};
  };
  // Two passes by chunks, as MakeSurface over the moved points: their
  // finite coordinates' range (the new origin), then the samples about it.
  const Execution execution = ExecutionFor(threads);
  const int64_t n = static_cast<int64_t>(surface.size());
  const int chunks = ChunksFor(n, int64_t{1} << 16);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<std::array<double, 3>> lo(chunks, {kInf, kInf, kInf}), hi(chunks, {-kInf, -kInf, -kInf});
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    std::array<double, 3> least = lo[c], most = hi[c];
    for (int64_t i = begin; i < end; ++i) {
      const std::array<double, 3> p = moved_point(static_cast<std::size_t>(i));
      for (int k = 0; k < 3; ++k) {
        if (std::isfinite(p[k])) least[k] = std::min(least[k], p[k]), most[k] = std::max(most[k], p[k]);
      }
    }
    lo[c] = least, hi[c] = most;
  });
  std::array<double, 3> least = lo[0], most = hi[0];
  for (int c = 1; c < chunks; ++c) {
    for (int k = 0; k < 3; ++k) least[k] = std::min(least[k], lo[c][k]), most[k] = std::max(most[k], hi[c][k]);
  }
  Surface moved;
  moved.source = surface.source;
  moved.origin = SurfaceOrigin(least, most, 1.0);
  moved.xy.resize(surface.size());
  moved.z.resize(surface.size());
  ForEachChunk(execution, n, chunks, [&](int, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const std::array<double, 3> p = moved_point(static_cast<std::size_t>(i));
      moved.xy[i] = {p[0] - moved.origin[0], p[1] - moved.origin[1]};
      moved.z[i] = p[2] - moved.origin[2];
    }
  });
  moved.weight = surface.weight;
  moved.raster_cell = surface.raster_cell;  // a rigidly moved raster keeps its cells
  return moved;
}

int AlignmentsAtOnce(std::size_t largest_samples, int pairs, int threads) {
  constexpr std::size_t kConcurrentSamples = 100000;
  constexpr int kMaxAtOnce = 8;  // bounds the memory of the alignments side by side
  if (largest_samples > kConcurrentSamples) return 1;
  return std::clamp(std::min(threads, pairs), 1, kMaxAtOnce);
}

}  // namespace surfreg

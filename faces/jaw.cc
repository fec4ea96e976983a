#include "faces/jaw.h"
#include "measure/tasks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>
#include <ceres/ceres.h>

#include "faces/jaw_internal.h"
#include "faces/jaw_split.h"
#include "measure/input_error.h"
#include "registration/axial_cost.h"
#include "registration/pair_state.h"
#include "registration/solvers.h"
#include "registration/volume_cost/volume_cost.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;
using Theta = std::array<double, 6>;
constexpr double kDegrees = 180.0 / 3.14159265358979323846;
double Seconds(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

// Squared distance from (x, y) to the segment a–b.
double SegmentDistance2(double x, double y, const std::array<double, 2>& a,
                        const std::array<double, 2>& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double length2 = dx * dx + dy * dy;
  double s = length2 > 0 ? ((x - a[0]) * dx + (y - a[1]) * dy) / length2 : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  const double ex = a[0] + s * dx - x, ey = a[1] + s * dy - y;
  return ex * ex + ey * ey;
}

// Point in polygon by crossings (half-open rule on y); the boundary itself
// is handled by the caller through the distance.
bool InsidePolygon(const std::vector<std::array<double, 2>>& polygon, double x, double y) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const auto& a = polygon[i];
    const auto& b = polygon[j];
    if ((a[1] > y) != (b[1] > y)) {
      const double cross_x = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x < cross_x) inside = !inside;
    }
  }
  return inside;
}

Eigen::Vector3d Apply(const Eigen::Matrix4d& m, double x, double y, double z) {
  return m.topLeftCorner<3, 3>() * Eigen::Vector3d(x, y, z) + m.topRightCorner<3, 1>();
}

}  // namespace

namespace jaw_internal {

Split SplitFrame(const Surface& frame, const Eigen::Matrix4d& reference_from_frame,
                 const JawBoundary& boundary) {
  Split split;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const std::array<double, 3> p = {frame.xy[i].x + frame.origin[0], frame.xy[i].y + frame.origin[1],
                                     frame.z[i] + frame.origin[2]};
    const Eigen::Vector3d q = Apply(reference_from_frame, p[0], p[1], p[2]);
    switch (ClassifyJawPoint(boundary, q.x(), q.y())) {
      case JawPart::kUpper: split.upper.push_back(p); break;
      case JawPart::kLower: split.lower.push_back(p); break;
      case JawPart::kDropped: ++split.dropped; break;
    }
  }
  return split;
}

Surface PartSurface(const Points& points, const std::string& name, int min_points) {
  if (static_cast<int>(points.size()) < min_points) {
    throw InputError(name + ": only " + std::to_string(points.size()) +
                     " points after the split (at least " + std::to_string(min_points) +
                     " needed); check the boundary and margin");
  }
  Surface surface = MakeSurface(points, {}, name);
  ValidateSurface(surface);
  return surface;
}

}  // namespace jaw_internal

namespace {

using jaw_internal::Points;

// Mean |r| over the active nodes (ρ'd), or NaN when none is active; their
// count in `active` if given.
double MeanAbsResidual(const PairState& state, int64_t* active = nullptr) {
  AxialResiduals residuals;
  ComputeAxialResiduals(state, AxialSettings(), false, &residuals);
  if (active != nullptr) *active = residuals.active_count;
  if (residuals.active_count == 0) return std::nan("");
  double sum = 0;
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (residuals.active[k]) sum += std::fabs(residuals.r[k]);
  }
  return sum / static_cast<double>(residuals.active_count);
}

// All node residuals of one part as ONE Ceres residual block over the six
// parameters (rotations × the part's RMS radius, so all are lengths).
// SolveAxial (solvers.h) builds one block per node so that a robust loss
// applies per node; with no loss here that costs Ceres ~0.1 s per part
// (40k blocks to set up and evaluate), more than the whole solve. Residuals
// and Jacobians are computed together at each new θ: Ceres asks for the
// Jacobian at an accepted θ right after its residuals.
class PartResiduals : public ceres::CostFunction {
 public:
  PartResiduals(PairState& state, const AxialSettings& settings, double scale)
      : state_(state), settings_(settings), scale_(scale) {
    set_num_residuals(static_cast<int>(state.reference().xy.size() + state.moving().points.size()));
    mutable_parameter_block_sizes()->push_back(6);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* x = parameters[0];
    if (!evaluated_ || !std::equal(x, x + 6, x_.begin())) {
      std::copy(x, x + 6, x_.begin());
      ok_ = state_.Update(ThetaOf(x));
      if (ok_) ComputeAxialResiduals(state_, settings_, true, &residuals_);
      evaluated_ = true;
    }
    if (!ok_) return false;  // folded: an infeasible step, Ceres shrinks it
    std::copy(residuals_.r.begin(), residuals_.r.end(), residuals);
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      double* out = jacobians[0];  // row-major, one row of 6 per node
      for (const std::array<double, 6>& row : residuals_.jacobian) {
        for (int i = 0; i < 6; ++i) *out++ = row[i] / (i < 3 ? scale_ : 1.0);
      }
    }
    return true;
  }
  Theta ThetaOf(const double* x) const {
    return {x[0] / scale_, x[1] / scale_, x[2] / scale_, x[3], x[4], x[5]};
  }

 private:
  PairState& state_;
  const AxialSettings& settings_;
  double scale_;
  mutable std::array<double, 6> x_{};
  mutable bool evaluated_ = false, ok_ = false;
  mutable AxialResiduals residuals_;  // reused: no per-step allocation
};

// Stops Ceres (as converged) after an accepted step shorter than step_tolerance.
class StepTolerance : public ceres::IterationCallback {
 public:
  explicit StepTolerance(double tolerance) : tolerance_(tolerance) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (summary.iteration > 0 && summary.step_is_successful && summary.step_norm < tolerance_) {
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double tolerance_;
};

struct AxialSolve {
  Theta theta{};
  double initial_cost = 0, final_cost = 0;
  int iterations = 0;
  bool converged = false, usable = false;
  std::string message;
};

// The axial cost of one part (the largest, cos-weighted if normal_distance,
// gaps trimmed; a mean over the kept nodes), minimized by Ceres'
// Levenberg-Marquardt from the warm start θ0. `overlap` (> 0): the nodes in
// the overlap at θ0.
AxialSolve SolveAxialPart(PairState& state, const Theta& theta0, double scale, int64_t overlap,
                          const JawOptions& options) {
  const AxialSettings settings = jaw_internal::PartSettings(options, overlap);
  std::array<double, 6> x{};
  for (int i = 0; i < 6; ++i) x[i] = theta0[i] * (i < 3 ? scale : 1.0);
  auto* cost = new PartResiduals(state, settings, scale);
  ceres::Problem problem;  // owns the cost function
  problem.AddResidualBlock(cost, nullptr, x.data());

  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // 6 unknowns, many rows
  solver.max_num_iterations = options.max_iterations;
  // The trimmed cost jumps as nodes enter or leave the kept set: relative
  // decreases below 1e-6 are that noise, not progress.
  solver.function_tolerance = 1e-6;
  solver.gradient_tolerance = 1e-16;
  solver.parameter_tolerance = 1e-10;  // step_tolerance (absolute) is the one that matters
  solver.num_threads = ExecutionFor(options.num_threads).threads;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  StepTolerance step(options.step_tolerance);
  solver.callbacks.push_back(&step);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  AxialSolve out;
  out.theta = cost->ThetaOf(x.data());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  out.converged = summary.termination_type == ceres::CONVERGENCE ||
                  summary.termination_type == ceres::USER_SUCCESS;
  out.usable = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  out.message = summary.message;
  return out;
}

void Describe(JawFrame* frame) {
  frame->euler_deg = EulerDegrees(frame->jaw.topLeftCorner<3, 3>());
  for (int k = 0; k < 3; ++k) frame->translation[k] = frame->jaw(k, 3);
}

}  // namespace

namespace jaw_internal {

AxialSettings PartSettings(const JawOptions& options, int64_t overlap) {
  AxialSettings settings;
  settings.trim_fraction = options.trim_fraction;
  settings.normal_distance = options.normal_distance;
  // A mean over the kept nodes (any constant count gives the same minimum):
  // otherwise sliding the part off the reference lowers the cost by dropping
  // nodes (axial_cost.h).
  settings.normalize_count = std::ceil((1.0 - options.trim_fraction) * static_cast<double>(overlap));
  return settings;
}

JawPartResult RegisterPart(const ReferencePart& reference, const Surface& part,
                           const Eigen::Matrix4d& warm, const JawOptions& options, bool measure) {
  JawPartResult result;
  result.points = static_cast<int>(part.size());
  const std::array<double, 3>& origin = reference.surface.origin;
  const std::array<double, 3> shift = {part.origin[0] - origin[0], part.origin[1] - origin[1],
                                       part.origin[2] - origin[2]};
  const MovingSide moving = PrepareMoving(part, shift);
  PairState state(reference.side, moving, options.max_fold_fraction);
  const Theta theta0 = ThetaOfRigid(Rigid3d::FromMatrix(warm), moving.centroid, origin);
  if (!state.Update(theta0)) {
    throw InputError(part.source + ": folds at the previous frame's motion (not a height field there)");
  }
  int64_t overlap = 0;
  result.rho_d_axial_before = MeanAbsResidual(state, &overlap);
  if (!std::isfinite(result.rho_d_axial_before)) {
    throw InputError(part.source + ": does not overlap the reference's part at the previous frame's motion");
  }
  const double scale = std::max(RmsRadius(moving), 1e-300);
  const AxialSolve solved = SolveAxialPart(state, theta0, scale, overlap, options);
  Theta theta = theta0;
  result.iterations = solved.iterations;
  if (!solved.usable) {
    result.verdict = Verdict::kFailed;
    result.verdict_reason = "no usable solution: " + solved.message;
  } else if (!solved.converged) {
    result.verdict = Verdict::kFailed;
    result.verdict_reason = "no convergence: " + solved.message;
    theta = solved.theta;
  } else if (!(solved.final_cost < solved.initial_cost)) {
    result.verdict = Verdict::kConvergedNotImproved;
    result.verdict_reason = "the measure did not decrease; the previous frame's motion is kept";
  } else {
    theta = solved.theta;
  }
  if (options.cost == JawCost::kVolume && options.volume_iterations > 0) {
    AlignOptions volume;
    volume.cost = CostKind::kVolume;
    volume.volume_solver.max_num_iterations = options.volume_iterations;
    volume.num_threads = options.num_threads;
    SolveContext volume_context;
    volume_context.options = &volume;
    volume_context.rotation_scale = scale;
    volume_context.cost = "volume";
    const SolveResult refined = SolveVolume(state, volume_context, theta);
    result.iterations += std::max(0, refined.iterations);
    if (refined.usable && refined.final_cost <= refined.initial_cost) theta = refined.theta;
  }
  state.Update(theta);
  result.rho_d_axial_after = MeanAbsResidual(state);
  if (measure) {
    const VolumeCostValue volume = EvaluateVolumeCost(state, false, ExecutionFor(options.num_threads));
    result.mean_abs_dz_after = volume.PerArea();
    result.overlap_area_after = volume.area;
    // Where the part ends (the axial solution, or the kept warm start, or
    // the volume refinement), with the settings it was solved with.
    const PartCovariance covariance =
        PartSandwichCovariance(state, PartSettings(options, overlap), scale);
    result.covariance_ok = covariance.ok;
    result.covariance = covariance.covariance;
    result.covariance_tiles = covariance.tiles;
    result.covariance_measured_curvature = covariance.measured_curvature;
  }
  result.reference_from_frame = RigidOfTheta(theta, moving.centroid, origin).ToMatrix();
  result.centre = moving.centroid + Eigen::Vector3d(origin[0], origin[1], origin[2]);
  return result;
}

}  // namespace jaw_internal

JawPart ClassifyJawPoint(const JawBoundary& boundary, double x, double y) {
  if (boundary.polygon.empty()) {
    if (std::fabs(y - boundary.y_level) < boundary.margin) return JawPart::kDropped;
    return y >= boundary.y_level ? JawPart::kUpper : JawPart::kLower;
  }
  double distance2 = std::numeric_limits<double>::infinity();
  const auto& polygon = boundary.polygon;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    distance2 = std::min(distance2, SegmentDistance2(x, y, polygon[j], polygon[i]));
  }
  if (distance2 == 0) return boundary.margin > 0 ? JawPart::kDropped : JawPart::kLower;
  if (distance2 < boundary.margin * boundary.margin) return JawPart::kDropped;
  return InsidePolygon(polygon, x, y) ? JawPart::kLower : JawPart::kUpper;
}

bool JawOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    *error = message;
    return false;
  };
  if (!std::isfinite(boundary.y_level)) return fail("boundary_y must be finite");
  if (!(boundary.margin >= 0) || !std::isfinite(boundary.margin)) return fail("boundary_margin must be >= 0");
  if (!boundary.polygon.empty() && boundary.polygon.size() < 3) {
    return fail("boundary_polygon needs at least 3 vertices");
  }
  for (const auto& v : boundary.polygon) {
    if (!std::isfinite(v[0]) || !std::isfinite(v[1])) return fail("boundary_polygon: vertices must be finite");
  }
  if (reference < 0) return fail("reference must be >= 0");
  if (!(trim_fraction >= 0 && trim_fraction < 0.5)) return fail("trim_fraction must be in [0, 0.5)");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(step_tolerance > 0) || !std::isfinite(step_tolerance)) return fail("step_tolerance must be > 0");
  if (volume_iterations < 0) return fail("volume_iterations must be >= 0");
  if (!(max_fold_fraction >= 0 && max_fold_fraction <= 1)) return fail("max_fold_fraction must be in [0, 1]");
  if (num_threads < 0) return fail("threads must be >= 1 (0: every core)");
  if (min_part_points < 3) return fail("min_part_points must be >= 3");
  if (path_point && !path_point->allFinite()) return fail("path_point must be finite");
  return true;
}

JawSummary TrackJaw(int count, const std::function<Surface(int)>& load, const JawOptions& options) {
  const Clock::time_point start = Clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw InputError("jaw options: " + error);
  if (count < 1) throw InputError("jaw: no frames");
  if (options.reference >= count) {
    throw InputError("jaw: reference frame " + std::to_string(options.reference) + " is beyond the " +
                     std::to_string(count) + " frames");
  }
  using namespace jaw_internal;  // NOLINT: the shared pieces of this file
  JawSummary summary;
  summary.reference = options.reference;
  summary.frames.resize(count);
  summary.boundary = options.boundary;
  if (options.find_boundary) {
    summary.boundary = FindJawBoundary(count, load, options, &summary.search);
    summary.boundary_found = true;
  }

  // The reference's parts, prepared once.
  ReferencePart upper, lower;
  Eigen::Vector3d& p0 = summary.path_reference;
  {
    const Clock::time_point frame_start = Clock::now();
    const Surface frame = load(options.reference);
    ValidateSurface(frame);
    const Split split = SplitFrame(frame, Eigen::Matrix4d::Identity(), summary.boundary);
    upper.surface = PartSurface(split.upper, frame.source + " (upper part)", options.min_part_points);
    lower.surface = PartSurface(split.lower, frame.source + " (lower part)", options.min_part_points);
    upper.side = PrepareReference(upper.surface);
    lower.side = PrepareReference(lower.surface);
    JawFrame& f = summary.frames[options.reference];
    f.index = options.reference;
    f.is_reference = true;
    f.upper.points = static_cast<int>(split.upper.size());
    f.lower.points = static_cast<int>(split.lower.size());
    f.dropped = split.dropped;
    summary.path_point_given = options.path_point.has_value();
    p0 = options.path_point ? *options.path_point : LowestPoint(split.lower);
    f.path_point = p0;
    f.seconds = Seconds(frame_start);
    Describe(&f);
    summary.reference_upper_points = f.upper.points;
    summary.reference_lower_points = f.lower.points;
    if (options.on_frame) options.on_frame(f);
  }

  // Outwards from the reference: forward, then backward.
  // The warm start of frame k from its neighbour k1 = k ∓ 1 and, with
  // `predict`, the one before it k2 = k ∓ 2 (constant velocity: the motion
  // from k2 to k1 repeated, M_k = M_k1 · M_k2⁻¹ · M_k1).
  auto warm = [&](int neighbour, int second, bool upper_part) {
    const Eigen::Matrix4d& m1 = (upper_part ? summary.frames[neighbour].upper : summary.frames[neighbour].lower)
                                    .reference_from_frame;
    if (!options.predict || second < 0 || second >= count) return m1;
    const Eigen::Matrix4d& m2 = (upper_part ? summary.frames[second].upper : summary.frames[second].lower)
                                    .reference_from_frame;
    return Eigen::Matrix4d(m1 * m2.inverse() * m1);
  };
  // The two parts of a frame are registered side by side, one thread each
  // (a part's few thousand points keep one thread busy; the numbers do not
  // depend on the threads).
  const bool side_by_side = ExecutionFor(options.num_threads).parallel();
  JawOptions part_options = options;
  if (side_by_side) part_options.num_threads = 1;
  auto track = [&](int k, int neighbour) {
    const Clock::time_point frame_start = Clock::now();
    const Surface frame = load(k);
    ValidateSurface(frame);
    const int second = 2 * neighbour - k;
    const Eigen::Matrix4d warm_upper = warm(neighbour, second, true);
    const Eigen::Matrix4d warm_lower = warm(neighbour, second, false);
    const Split split = SplitFrame(frame, warm_upper, summary.boundary);
    JawFrame& f = summary.frames[k];
    f.index = k;
    f.dropped = split.dropped;
    const Surface upper_part = PartSurface(split.upper, frame.source + " (upper part)", options.min_part_points);
    const Surface lower_part = PartSurface(split.lower, frame.source + " (lower part)", options.min_part_points);
    // Both parts run to their end; then the upper part's error first.
    ForEachItem(ExecutionFor(side_by_side ? 2 : 1), 2, [&](int part) {
      if (part == 0) {
        f.upper = RegisterPart(upper, upper_part, warm_upper, part_options);
      } else {
        f.lower = RegisterPart(lower, lower_part, warm_lower, part_options);
      }
    });
    f.jaw = f.upper.reference_from_frame * f.lower.reference_from_frame.inverse();
    Describe(&f);
    PropagateFrameCovariance(p0, &f);
    f.seconds = Seconds(frame_start);
    if (f.upper.verdict == Verdict::kFailed || f.lower.verdict == Verdict::kFailed) ++summary.failed_frames;
    if (options.on_frame) options.on_frame(f);
  };
  for (int k = options.reference + 1; k < count; ++k) track(k, k - 1);
  for (int k = options.reference - 1; k >= 0; --k) track(k, k + 1);
  for (int k = 0; k + 1 < count; ++k) {
    summary.helical_axes.push_back(RelativeHelicalAxis(summary.frames[k].jaw, summary.frames[k + 1].jaw));
  }
  summary.seconds = Seconds(start);
  return summary;
}

JawSummary TrackJaw(const std::vector<Surface>& frames, const JawOptions& options) {
  return TrackJaw(static_cast<int>(frames.size()), [&frames](int k) { return frames[k]; }, options);
}

std::array<double, 2> MotionDifference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  const Eigen::Matrix3d r = a.topLeftCorner<3, 3>() * b.topLeftCorner<3, 3>().transpose();
  const double angle = Eigen::AngleAxisd(r).angle() * kDegrees;
  const double shift = (a.topRightCorner<3, 1>() - b.topRightCorner<3, 1>()).norm();
  return {angle, shift};
}

}  // namespace surfreg

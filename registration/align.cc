#include "registration/align.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <memory>
#include <optional>
#include <random>

#include <Eigen/Cholesky>

#include "measure/input_error.h"
#include "measure/weights.h"
#include "registration/pair_state.h"
#include "registration/sandwich.h"
#include "registration/solvers.h"
#include "registration/wide_search.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

// wide_search auto also runs when the final mean gap exceeds this many
// sampling gaps (AlignResult::sampling_gap): the right pose leaves 0.13-0.42
// of it on the benchmark's 36 pairs, about 0.6 where noise dominates.
constexpr double kWideSearchGapFactor = 1.0;
// The axial prealignment runs on at most about this many points of each
// surface (AlignOptions::prealign).
constexpr double kPrealignPoints = 5000.0;


struct Level {
  ReferenceSide reference;
  MovingSide moving;
};

double RmsRadius(const MovingSide& side) {
  double sum = 0;
  for (const Eigen::Vector3d& p : side.points) sum += (p - side.centroid).squaredNorm();
  return std::sqrt(sum / static_cast<double>(side.points.size()));
}

// The mean gap two samplings of one surface leave at the right pose, about:
// over inner vertices of the data domain (every k-th, at most ~4000), the
// mean vertical distance from the vertex to the least-squares plane through
// its Delaunay neighbours, i.e. the surface's own interpolation error plus
// its noise (pair_state.h PlaneGaps).
double InterpolationGap(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                        const std::vector<uint8_t>& domain) {
  const std::vector<uint8_t> inner = InteriorVertices(mesh, points.size(), domain);
  const std::vector<double> gap = PlaneGaps(points, mesh, std::max<std::size_t>(1, points.size() / 4000));
  double sum = 0;
  int64_t count = 0;
  for (std::size_t v = 0; v < points.size(); ++v)
    if (inner[v] && gap[v] >= 0) {
      sum += gap[v];
      ++count;
    }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

// Moving input → reference input for θ about centre c (A's local frame).
Eigen::Matrix4d MatrixOf(const std::array<double, 6>& theta, const Eigen::Vector3d& centre_local,
                         const std::array<double, 3>& reference_origin) {
  const Eigen::Matrix3d rotation = RotationMatrix({theta[0], theta[1], theta[2]});
  const Eigen::Vector3d centre =
      centre_local + Eigen::Vector3d(reference_origin[0], reference_origin[1], reference_origin[2]);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation;
  m.topRightCorner<3, 1>() = centre + Eigen::Vector3d(theta[3], theta[4], theta[5]) - rotation * centre;
  return m;
}

// The deterministic perturbation of multi-start s ≥ 1: a random axis and
// direction (seeded by s), of the configured magnitudes, free parameters only.
std::array<double, 6> Perturbed(const std::array<double, 6>& theta, int s,
                                const AlignOptions& options, double shift) {
  if (s == 0) return theta;
  std::mt19937_64 rng(0x5eed0000ULL + static_cast<uint64_t>(s));
  std::normal_distribution<double> normal;
  Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng)), direction(normal(rng), normal(rng), normal(rng));
  axis.normalize();
  direction.normalize();
  const double angle = options.multi_start_angle_deg * M_PI / 180.0;
  std::array<double, 6> out = theta;
  for (int k = 0; k < 3; ++k) {
    if (options.free[k]) out[k] += angle * axis[k];
    if (options.free[3 + k]) out[3 + k] += shift * direction[k];
  }
  return out;
}

MeasureOptions MeasureOptionsFor(const AlignOptions& options) {
  MeasureOptions m;
  m.weight = options.weight;
  m.mask_polygon = options.mask_polygon;
  m.domain = options.domain;
  m.parallel = options.num_threads > 1;
  return m;
}

double MeasureOfCost(const AlignOptions& options, const MeasureSummary& s) {
  return options.cost == CostKind::kAxial ? s.rho_d_axial : s.mean_abs_dz;
}

}  // namespace

namespace {

// `motion_only`: only the solved motion (rotation_vector, translation) and
// a verdict from the solver alone (converged or failed): no measures, no
// information; for the subsample σ's many small alignments.
// The information at the state's motion and, by default, the sandwich
// covariance of the cost (registration/sandwich.h); `source` names the one
// that holds.
Information StddevAt(PairState& state, const SolveContext& context, const AlignOptions& options,
                     std::string* source) {
  Information info = AnalyseInformation(state, context, options.compute_covariance);
  *source = "information";
  const bool sandwich_wanted = options.stddev_method == AlignOptions::StddevMethod::kSandwich &&
                               options.compute_covariance && options.stddev_subsamples == 0 && info.covariance_ok;
  if (!sandwich_wanted) return info;
  // Steps of the information σ: on noisy terrain the sandwich's σ hardly
  // depends on them (1 × or 3 × gave the same calibration on the 120
  // peer pairs); on clean faces, where the L1 cost is nearly a cone at
  // the solution, a second pass with the sandwich's own σ as the step
  // moved the median |error| / σ only from 0.03 to 0.06.
  std::array<double, 6> step{};
  for (int i = 0; i < 6; ++i) step[i] = std::sqrt(std::max(0.0, info.covariance(i, i)));
  const SandwichEstimate sandwich = options.cost == CostKind::kAxial
                                        ? AxialSandwichCovariance(state, context, step)
                                        : SandwichCovariance(state, context, step);
  if (sandwich.ok) {
    info.covariance = sandwich.covariance;
    *source = "sandwich over " + std::to_string(sandwich.tiles) + " tiles";
  }
  return info;
}

AlignResult AlignFrom(const Surface& reference, const Surface& moving, const AlignOptions& options_in,
                      bool motion_only = false) {
  const Clock::time_point start = Clock::now();
  std::string error;
  if (!options_in.IsValid(&error)) throw InputError("align options: " + error);
  if (options_in.weight == WeightMode::kPerPoint) {
    // μ lives on the reference's mesh: the reference is fixed, so μ is too.
    const std::string name = reference.source.empty() ? "the reference" : reference.source;
    if (reference.weight.empty()) {
      throw InputError("align: weight per_point needs per-sample weights on the reference, but " +
                       name + " has none");
    }
    const auto positive = [](double w) { return w > 0; };
    if (std::none_of(reference.weight.begin(), reference.weight.end(), positive)) {
      throw InputError("align: weight per_point: every weight of " + name + " is 0");
    }
  }
  AlignOptions options = options_in;
  const std::array<double, 3> shift = {moving.origin[0] - reference.origin[0],
                                       moving.origin[1] - reference.origin[1],
                                       moving.origin[2] - reference.origin[2]};
  // Levels, coarsest first; all share the full cloud's centroid so θ means
  // the same motion on every level.
  std::vector<std::unique_ptr<Level>> levels;
  for (int l = 0; l < options.levels; ++l) {
    const double keep = options.subsample * std::pow(options.level_factor, -(options.levels - 1 - l));
    auto level = std::make_unique<Level>();
    level->reference = PrepareReference(reference, keep, options.domain);  // weights kept per point
    if (options.weight != WeightMode::kPerPoint) level->reference.weight.clear();
    if (options.cost == CostKind::kVolume) {
      ApplySlopeWeight(options.slope_weight, &level->reference);
      ApplyGapWeight(options.gap_weight, &level->reference);
    }
    level->moving = PrepareMoving(moving, shift, keep, options.domain);
    levels.push_back(std::move(level));
  }
  Level& finest = *levels.back();
  // A subsampled finest level has its own centroid; θ keeps meaning a motion
  // about the full cloud's.
  if (options.subsample < 1) finest.moving.centroid = PrepareMoving(moving, shift).centroid;
  for (auto& level : levels) level->moving.centroid = finest.moving.centroid;

  SolveContext context;
  context.options = &options;
  context.rotation_scale = std::max(RmsRadius(finest.moving), 1e-300);
  for (const auto& p : options.mask_polygon) {
    context.axial.mask.push_back({p[0] - reference.origin[0], p[1] - reference.origin[1]});
  }
  context.axial.trim_fraction = options.trim_fraction;
  context.axial.normal_distance = options.normal_distance;
  if (!context.axial.mask.empty()) context.mask_triangles = TriangulatePolygon(context.axial.mask);

  AlignResult result;
  const std::array<double, 6> theta0 = {options.initial_rotation[0], options.initial_rotation[1],
                                        options.initial_rotation[2], options.initial_translation[0],
                                        options.initial_translation[1], options.initial_translation[2]};
  {
    PairState check(finest.reference, finest.moving, options.max_fold_fraction);
    UpdateStats stats;
    if (!check.Update(theta0, &stats)) {
      throw InputError("the initial motion folds " + moving.source + ": " +
                       std::to_string(stats.folded) +
                       " triangles turn over in the xy projection (tilt too large for a height field)");
    }
    if (options.cost == CostKind::kAxial && options.loss != LossKind::kNone &&
        !(options.loss_scale > 0)) {
      options.loss_scale = AutomaticLossScale(check, context.axial, 1e-9 * context.rotation_scale);
    }
  }
  const Eigen::Vector3d centre = finest.moving.centroid;
  const MeasureOptions measure_options = MeasureOptionsFor(options);
  // The measure before the motion is needed only for the verdict: it runs
  // beside the solve, whose prealignment keeps one core busy.
  std::future<MeasureSummary> before;
  if (!motion_only) {
    before = std::async(std::launch::async, [&reference, &moving, &measure_options, theta0, centre] {
      return Measure(reference, TransformSurface(moving, MatrixOf(theta0, centre, reference.origin)),
                     measure_options);
    });
  }
  if (options.on_stage) options.on_stage("solving", Seconds(start));
  SolveResult best;
  bool have_best = false;
  int iterations = 0;
  try {
    std::array<double, 6> start_theta = theta0;
    if (options.wide_search == AlignOptions::WideSearch::kAlways) {
      const double keep_a = std::min(1.0, 2000.0 / static_cast<double>(reference.size()));
      const double keep_b = std::min(1.0, 2000.0 / static_cast<double>(moving.size()));
      const ReferenceSide coarse_reference = PrepareReference(reference, keep_a, options.domain);
      MovingSide coarse_moving = PrepareMoving(moving, shift, keep_b, options.domain);
      coarse_moving.centroid = finest.moving.centroid;  // θ: the same motion on every level
      start_theta = WideSearch(coarse_reference, coarse_moving, theta0, options, context.rotation_scale).theta;
      result.wide_search_ran = true;
    }
    const double spacing = std::sqrt(finest.moving.hull_area / static_cast<double>(finest.moving.points.size()));
    const double start_shift = options.multi_start_shift > 0 ? options.multi_start_shift : 5.0 * spacing;
    // The axial prealignment only has to land in the volume cost's basin: on
    // large clouds it runs on a fixed subsample of at most kPrealignPoints of
    // each (its time otherwise rivals the volume solve's).
    std::optional<Level> prealign_sides;
    const Level& coarsest = *levels.front();
    const double keep_a = std::min(1.0, kPrealignPoints / static_cast<double>(coarsest.reference.xy.size()));
    const double keep_b = std::min(1.0, kPrealignPoints / static_cast<double>(coarsest.moving.points.size()));
    if (options.cost == CostKind::kVolume && options.prealign && std::min(keep_a, keep_b) < 1) {
      const double level_keep = options.subsample * std::pow(options.level_factor, -(options.levels - 1));
      prealign_sides.emplace();
      prealign_sides->reference = PrepareReference(reference, level_keep * keep_a, options.domain);
      if (options.weight != WeightMode::kPerPoint) prealign_sides->reference.weight.clear();
      prealign_sides->moving = PrepareMoving(moving, shift, level_keep * keep_b, options.domain);
      prealign_sides->moving.centroid = finest.moving.centroid;
    }
    for (int s = 0; s <= options.multi_start; ++s) {
      std::array<double, 6> theta = Perturbed(start_theta, s, options, start_shift);
      SolveResult solved;
      bool usable = true;
      for (std::size_t l = 0; l < levels.size() && usable; ++l) {
        PairState state(levels[l]->reference, levels[l]->moving, options.max_fold_fraction);
        context.level = static_cast<int>(l);
        context.start = s;
        context.seconds_offset = Seconds(start);
        context.log = &result.log;
        if (options.cost == CostKind::kVolume && options.prealign && l == 0) {
          context.cost = "axial";
          std::optional<PairState> subsampled;  // each start from the sides' own meshes
          if (prealign_sides) {
            subsampled.emplace(prealign_sides->reference, prealign_sides->moving, options.max_fold_fraction);
          }
          context.prealignment = true;
          const SolveResult rough = SolveAxial(subsampled ? *subsampled : state, context, theta);
          context.prealignment = false;
          iterations += std::max(0, rough.iterations);
          if (rough.usable) theta = rough.theta;
        }
        context.cost = options.cost == CostKind::kAxial ? "axial" : "volume";
        context.seconds_offset = Seconds(start);
            solved = options.cost == CostKind::kAxial ? SolveAxial(state, context, theta)
                                                  : SolveVolume(state, context, theta);
        iterations += std::max(0, solved.iterations);
        result.remeshes += state.remeshes();
        usable = solved.usable;
        if (usable) theta = solved.theta;
      }
      if (usable && (!have_best || solved.final_cost < best.final_cost)) {
        best = solved;
        have_best = true;
      }
    }
  } catch (...) {
    // A measure that failed (e.g. surfaces that do not overlap) is the error
    // to report, not what the solve made of such input.
    if (before.valid()) before.get();
    throw;
  }
  if (!motion_only) result.before = before.get();
  result.iterations = iterations;
  if (motion_only) {
    const std::array<double, 6> solved = have_best ? best.theta : theta0;
    for (int k = 0; k < 3; ++k) {
      result.rotation_vector[k] = solved[k];
      result.translation[k] = solved[3 + k];
    }
    result.verdict = have_best && best.converged ? Verdict::kConvergedImproved : Verdict::kFailed;
    return result;
  }

  std::array<double, 6> theta = have_best ? best.theta : theta0;
  result.termination = have_best ? best.message : "no usable solution";
  if (options.on_stage) options.on_stage("measuring the result", Seconds(start));
  PairState final_state(finest.reference, finest.moving, options.max_fold_fraction);
  UpdateStats stats;
  const bool unfolded = final_state.Update(theta, &stats);
  result.folded_triangles = stats.folded;
  result.folded_area_fraction = stats.folded_area_fraction;
  bool failed = !have_best || !unfolded;
  std::string reason = !have_best ? "the solver found no usable solution"
                       : !unfolded ? "the moving surface folds at the solution"
                                   : "";
  // The measure after the motion runs beside the standard deviations at
  // the solution (needed again only if the verdict keeps the start).
  Information info;
  bool info_at_theta = false;
  if (!failed) {
    std::future<MeasureSummary> after =
        std::async(std::launch::async, [&reference, &moving, &measure_options, theta, centre] {
          return Measure(reference, TransformSurface(moving, MatrixOf(theta, centre, reference.origin)),
                         measure_options);
        });
    const Clock::time_point information_start = Clock::now();
    info = StddevAt(final_state, context, options, &result.stddev_source);
    result.covariance_seconds = Seconds(information_start);
    info_at_theta = true;
    try {
      result.after = after.get();
    } catch (const InputError& e) {
      failed = true;
      reason = std::string("the surfaces no longer overlap at the solution: ") + e.what();
    }
  }
  const double before_measure = MeasureOfCost(options, result.before);
  bool keep_initial = failed;
  if (failed) {
    result.verdict = Verdict::kFailed;
  } else if (!(MeasureOfCost(options, result.after) < before_measure)) {
    keep_initial = true;
    result.verdict = best.converged ? Verdict::kConvergedNotImproved : Verdict::kFailed;
    reason = "the measure did not decrease; the initial motion is kept";
  } else if (!best.converged) {
    result.verdict = Verdict::kFailed;
    reason = "no convergence within max_iterations (" + best.message + ")";
  } else {
    result.verdict = Verdict::kConvergedImproved;
  }
  if (keep_initial) {
    theta = theta0;
    result.after = result.before;
    final_state.Update(theta, &stats);
  }

  if (keep_initial || !info_at_theta) {
    const Clock::time_point again = Clock::now();
    info = StddevAt(final_state, context, options, &result.stddev_source);
    result.covariance_seconds = Seconds(again);
  }
  result.observability = info.observability;
  result.constrained = info.constrained;
  result.condition_number = info.condition_number;
  if (info.covariance_ok) {
    result.covariance = info.covariance;
    for (int k = 0; k < 6; ++k) {
      if (!options.free[k]) result.covariance.row(k).setZero(), result.covariance.col(k).setZero();
    }
  }
  for (int k = 0; k < 6; ++k) {
    result.stddev[k] = !options.free[k] ? 0.0
                       : info.covariance_ok ? std::sqrt(std::max(0.0, info.covariance(k, k)))
                                            : std::nan("");
  }
  if (result.verdict == Verdict::kConvergedImproved) {
    std::string loose;
    for (int k = 0; k < 6; ++k) {
      if (options.free[k] && !info.constrained[k]) loose += std::string(loose.empty() ? "" : ", ") + kParameterNames[k];
    }
    if (!loose.empty()) {
      result.verdict = Verdict::kIllConditioned;
      reason = "not determined by the data (flat or featureless surface): " + loose;
    }
  }
  result.verdict_reason = reason;

  result.motion = MotionOf(finest.moving, theta);
  result.matrix = MatrixOf(theta, centre, reference.origin);
  for (int k = 0; k < 3; ++k) {
    result.rotation_vector[k] = theta[k];
    result.translation[k] = theta[3 + k];
    result.centre[k] = centre[k] + reference.origin[k];
  }
  const Eigen::Vector4d q = MotionQuaternion(result.motion);
  result.quaternion = {q[0], q[1], q[2], q[3]};
  result.euler_deg = EulerDegrees(result.matrix.topLeftCorner<3, 3>());
  auto fraction = [](const MeasureSummary& s) {
    return s.overlap_area / std::min(s.domain_area_a, s.domain_area_b);
  };
  result.overlap_fraction_before = fraction(result.before);
  result.overlap_fraction_after = fraction(result.after);
  const ReferenceSide& a = finest.reference;
  const MovingSide& b = finest.moving;
  std::vector<Eigen::Vector3d> points_a(a.xy.size());
  for (std::size_t v = 0; v < a.xy.size(); ++v) points_a[v] = {a.xy[v].x, a.xy[v].y, a.z[v]};
  result.sampling_gap = InterpolationGap(points_a, a.mesh, a.domain) + InterpolationGap(b.points, b.mesh, b.domain);
  result.seconds = Seconds(start);
  return result;
}

}  // namespace

namespace {

// Align, and the wide search when the verdict asks for it.
AlignResult AlignWithSearch(const Surface& reference, const Surface& moving, const AlignOptions& options) {
  AlignResult result = AlignFrom(reference, moving, options);
  // A wrong minimum: the solver failed or did not improve, or the surfaces
  // still lie apart by far more than two samplings of one surface do at the
  // right pose (AlignResult::sampling_gap). A start already at the minimum
  // (a previous run's result) does not improve either, but its surfaces lie
  // as close as samplings do: nothing to search for.
  const bool close = result.sampling_gap > 0 &&
                     MeasureOfCost(options, result.after) <= kWideSearchGapFactor * result.sampling_gap;
  const bool poor = result.verdict == Verdict::kFailed ||
                    (result.verdict == Verdict::kConvergedNotImproved && !close);
  const bool apart = result.verdict == Verdict::kConvergedImproved && result.sampling_gap > 0 && !close;
  if (options.wide_search != AlignOptions::WideSearch::kAuto || !(poor || apart)) return result;
  AlignOptions wide = options;
  wide.wide_search = AlignOptions::WideSearch::kAlways;
  AlignResult second = AlignFrom(reference, moving, wide);
  second.seconds += result.seconds;
  second.wide_search_ran = result.wide_search_ran = true;
  // Real change between the surfaces also leaves them apart: then the search
  // finds the same minimum, or a worse one, and the first result stays.
  const bool better = second.verdict == Verdict::kConvergedImproved &&
                      (poor || MeasureOfCost(options, second.after) < MeasureOfCost(options, result.after));
  if (better) return second;
  result.seconds = second.seconds;
  return result;
}

// σ from alignments on block half-samples of the reference (AlignOptions::
// stddev_subsamples), started at `result`'s motion.
void SubsampleStddev(const Surface& reference, const Surface& moving, const AlignOptions& options,
                     AlignResult* result) {
  AlignOptions sub = options;
  sub.stddev_subsamples = 0;
  sub.holdout_fraction = 0;
  sub.wide_search = AlignOptions::WideSearch::kNever;
  sub.compute_covariance = false;
  sub.prealign = false;
  sub.multi_start = 0;
  sub.levels = 1;
  sub.on_iteration = nullptr;
  sub.on_stage = nullptr;
  sub.initial_rotation = result->rotation_vector;
  sub.initial_translation = result->translation;
  Eigen::Matrix<double, 6, 6> sum = Eigen::Matrix<double, 6, 6>::Zero();
  int used = 0;
  for (int k = 0; k < options.stddev_subsamples; ++k) {
    const std::vector<uint8_t> half = HeldOutSamples(reference, 0.5, 7919u * static_cast<uint64_t>(k + 1));
    AlignResult r;
    try {
      r = AlignFrom(WithoutSamples(reference, half), moving, sub, /*motion_only=*/true);
    } catch (const InputError&) {
      continue;  // a half without overlap: no estimate
    }
    if (r.verdict == Verdict::kFailed) continue;
    Eigen::Matrix<double, 6, 1> d;
    for (int i = 0; i < 3; ++i) {
      d[i] = r.rotation_vector[i] - result->rotation_vector[i];
      d[3 + i] = r.translation[i] - result->translation[i];
    }
    for (int i = 0; i < 6; ++i) {
      if (!options.free[i]) d[i] = 0;
    }
    sum += d * d.transpose();
    ++used;
  }
  result->stddev_source = "block half-samples";
  result->covariance = used > 0 ? Eigen::Matrix<double, 6, 6>(sum / used)
                                : Eigen::Matrix<double, 6, 6>::Constant(std::nan(""));
  for (int i = 0; i < 6; ++i) {
    result->stddev[i] = !options.free[i] ? 0.0 : used > 0 ? std::sqrt(result->covariance(i, i)) : std::nan("");
  }
}

}  // namespace

AlignResult Align(const Surface& reference, const Surface& moving, const AlignOptions& options) {
  if (options.stddev_subsamples > 0) {
    AlignOptions main = options;
    main.stddev_subsamples = 0;
    main.stddev_method = AlignOptions::StddevMethod::kInformation;  // replaced below
    AlignResult result = Align(reference, moving, main);
    const Clock::time_point start = Clock::now();
    SubsampleStddev(reference, moving, options, &result);
    result.covariance_seconds += Seconds(start);
    result.seconds += Seconds(start);
    return result;
  }
  if (!(options.holdout_fraction > 0)) return AlignWithSearch(reference, moving, options);
  std::string error;
  if (!options.IsValid(&error)) throw InputError("align options: " + error);
  const std::vector<uint8_t> held = HeldOutSamples(reference, options.holdout_fraction, options.holdout_seed);
  AlignOptions fit = options;
  fit.holdout_fraction = 0;
  AlignResult result = AlignWithSearch(WithoutSamples(reference, held), moving, fit);
  const Clock::time_point start = Clock::now();
  HoldoutCheck& check = result.holdout;
  check.fraction = options.holdout_fraction;
  std::vector<bool> keep(held.begin(), held.end());
  check.samples = std::count(held.begin(), held.end(), uint8_t{1});
  // dz on the whole reference, kept where held out.
  MeasureOptions m = MeasureOptionsFor(options);
  m.keep_node_gaps = true;
  const Eigen::Vector3d centre_local(result.centre[0] - reference.origin[0], result.centre[1] - reference.origin[1],
                                     result.centre[2] - reference.origin[2]);
  const std::array<double, 6> theta0 = {options.initial_rotation[0], options.initial_rotation[1],
                                        options.initial_rotation[2], options.initial_translation[0],
                                        options.initial_translation[1], options.initial_translation[2]};
  const Eigen::Matrix4d initial = MatrixOf(theta0, centre_local, reference.origin);
  check.before = ComputeDzStatistics(Measure(reference, TransformSurface(moving, initial), m).dz_a, keep);
  check.after = ComputeDzStatistics(Measure(reference, TransformSurface(moving, result.matrix), m).dz_a, keep);
  check.robust_before = RobustRmse(check.before);
  check.robust_after = RobustRmse(check.after);
  check.improved = check.robust_after < check.robust_before;
  check.done = true;
  if (options.holdout_verdict && result.verdict == Verdict::kConvergedImproved && !check.improved) {
    char reason[200];
    std::snprintf(reason, sizeof reason,
                  "the held-out %.0f%% of the reference did not improve (robust RMSE of dz %.4g -> %.4g)",
                  100 * options.holdout_fraction, check.robust_before, check.robust_after);
    result.verdict = Verdict::kConvergedNotImproved;
    result.verdict_reason = reason;
  }
  result.seconds += Seconds(start);
  return result;
}

}  // namespace surfreg

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
#include "measure/tasks.h"
#include "measure/weights.h"
#include "registration/align_stable.h"
#include "registration/align_steps.h"
#include "registration/gap_weight.h"
#include "registration/pair_state.h"
#include "registration/sandwich.h"
#include "registration/solvers.h"
#include "registration/wide_search.h"

namespace surfreg {
namespace {

using align_steps::Clock;
using align_steps::Level;
using align_steps::Seconds;
using align_steps::Starts;

// wide_search auto also runs when the final mean gap exceeds this many
// sampling gaps (AlignResult::sampling_gap): the right pose leaves 0.13-0.42
// of it on the benchmark's 36 pairs, about 0.6 where noise dominates.
constexpr double kWideSearchGapFactor = 1.0;


// The mean gap two samplings of one surface leave at the right pose, about:
// over inner vertices of the data domain (every k-th, at most ~4000), the
// mean vertical distance from the vertex to the least-squares plane through
// its Delaunay neighbours, i.e. the surface's own interpolation error plus
// its noise (gap_weight.h PlaneGaps).
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

// The start as θ about `centre` (A's local frame).
std::array<double, 6> InitialTheta(const AlignOptions& options, const Eigen::Vector3d& centre,
                                   const std::array<double, 3>& reference_origin) {
  if (options.initial_reference_from_moving) {
    return ThetaOfRigid(*options.initial_reference_from_moving, centre, reference_origin);
  }
  return {options.initial_rotation[0], options.initial_rotation[1], options.initial_rotation[2],
          options.initial_translation[0], options.initial_translation[1], options.initial_translation[2]};
}

MeasureOptions MeasureOptionsFor(const AlignOptions& options) {
  MeasureOptions m;
  m.weight = options.weight;
  m.mask = options.mask;
  m.mask_mode = options.mask_mode;
  m.domain = options.domain;
  m.threads = options.num_threads;
  m.keep_node_gaps = options.keep_node_gaps;
  return m;
}

}  // namespace

double MeasureOfCost(CostKind cost, const MeasureSummary& s) {
  return cost == CostKind::kAxial || cost == CostKind::kAxialSparser ? s.rho_d_axial : s.mean_abs_dz;
}

// A wrong minimum: the solver failed or did not improve, or the surfaces
// still lie apart by far more than two samplings of one surface do at the
// right pose (AlignResult::sampling_gap). A start already at the minimum
// (a previous run's result) does not improve either, but its surfaces lie
// as close as samplings do: nothing to search for.
bool WideSearchWanted(const AlignResult& result, CostKind cost) {
  const bool close = result.sampling_gap > 0 && MeasureOfCost(cost, result.after) <= kWideSearchGapFactor * result.sampling_gap;
  const bool poor = result.verdict == Verdict::kFailed || (result.verdict == Verdict::kConvergedNotImproved && !close);
  const bool apart = result.verdict == Verdict::kConvergedImproved && result.sampling_gap > 0 && !close;
  return poor || apart;
}

namespace {

// The information at the state's motion and, by default, the sandwich
// covariance of the cost (registration/sandwich.h); `source` names the one
// that holds.
// `solved`, `cache`: the volume solve's state at θ and its overlay cache, for
// the sandwich (else it uses `state`).
Information StddevAt(PairState& state, const SolveContext& context, const AlignOptions& options,
                     std::string* source, PairState* solved = nullptr, VolumeCostCache* cache = nullptr) {
  Information info = AnalyseInformation(state, context, options.compute_covariance);
  *source = "information";
  const bool sandwich_wanted = options.stddev_method == AlignOptions::StddevMethod::kSandwich &&
                               options.compute_covariance && options.stddev_subsamples == 0 && info.covariance_ok;
  if (!sandwich_wanted) return info;
  // The axial bread's central differences span the information σ: the
  // axial cost jumps as nodes enter and leave Ω, and small steps there see
  // those jumps (1.15 → 1.81 RMS error / σ under Gaussian noise,
  // stddev_calibration_test). The volume cost's bread is in closed form.
  const SandwichEstimate sandwich = [&] {
    if (context.solve_cost != CostKind::kAxial) {
      return solved != nullptr ? SandwichCovariance(*solved, context, cache) : SandwichCovariance(state, context);
    }
    std::array<double, 6> step{};
    for (int i = 0; i < 6; ++i) step[i] = std::sqrt(std::max(0.0, info.covariance(i, i)));
    return AxialSandwichCovariance(state, context, step);
  }();
  if (sandwich.ok) {
    info.covariance = sandwich.covariance;
    *source = "sandwich over " + std::to_string(sandwich.tiles) + " tiles";
  }
  return info;
}

// The standard deviations, the covariance and what the data leave
// undetermined (ill-conditioned) into `result`.
void SetStddev(const Information& info, const AlignOptions& options, AlignResult* result, std::string* reason) {
  result->observability = info.observability;
  result->constrained = info.constrained;
  result->condition_number = info.condition_number;
  if (info.covariance_ok) {
    result->covariance = info.covariance;
    for (int k = 0; k < 6; ++k) {
      if (!options.free[k]) result->covariance.row(k).setZero(), result->covariance.col(k).setZero();
    }
  }
  for (int k = 0; k < 6; ++k) {
    result->stddev[k] = !options.free[k] ? 0.0
                        : info.covariance_ok ? std::sqrt(std::max(0.0, info.covariance(k, k)))
                                             : std::nan("");
  }
  if (result->verdict != Verdict::kConvergedImproved) return;
  std::string loose;
  for (int k = 0; k < 6; ++k) {
    if (options.free[k] && !info.constrained[k]) loose += std::string(loose.empty() ? "" : ", ") + kParameterNames[k];
  }
  if (!loose.empty()) {
    result->verdict = Verdict::kIllConditioned;
    *reason = "not determined by the data (flat or featureless surface): " + loose;
  }
}

// The motion θ (about `centre`, A's local frame) in every form, the
// overlaps, and the sampling gap of the two surfaces.
void SetMotion(const std::array<double, 6>& theta, const Eigen::Vector3d& centre, const Level& finest,
               const Surface& reference, AlignResult* result) {
  result->motion = MotionOf(finest.moving, theta);
  result->reference_from_moving = RigidOfTheta(theta, centre, reference.origin);
  result->matrix = result->reference_from_moving.ToMatrix();
  for (int k = 0; k < 3; ++k) {
    result->rotation_vector[k] = theta[k];
    result->translation[k] = theta[3 + k];
    result->centre[k] = centre[k] + reference.origin[k];
  }
  const Eigen::Vector4d q = MotionQuaternion(result->motion);
  result->quaternion = {q[0], q[1], q[2], q[3]};
  result->euler_deg = EulerDegrees(result->matrix.topLeftCorner<3, 3>());
  auto fraction = [](const MeasureSummary& s) { return s.overlap_area / std::min(s.domain_area_a, s.domain_area_b); };
  result->overlap_fraction_before = fraction(result->before);
  result->overlap_fraction_after = fraction(result->after);
  const ReferenceSide& a = finest.reference;
  const MovingSide& b = finest.moving;
  std::vector<Eigen::Vector3d> points_a(a.xy.size());
  for (std::size_t v = 0; v < a.xy.size(); ++v) points_a[v] = {a.xy[v].x, a.xy[v].y, a.z[v]};
  result->sampling_gap = InterpolationGap(points_a, a.mesh, a.domain) + InterpolationGap(b.points, b.mesh, b.domain);
  result->density_ratio = finest.density.ratio;
  result->chord_correction = !finest.density.applied ? "none" : finest.density.reference ? "reference" : "moving";
}

// The verdict from the solve and the two measures; true if the initial
// motion is to be kept (the solve failed or did not lower the measure).
bool Judge(const Starts& starts, CostKind cost, bool failed, AlignResult* result, std::string* reason) {
  if (failed) {
    result->verdict = Verdict::kFailed;
    return true;
  }
  if (!(MeasureOfCost(cost, result->after) < MeasureOfCost(cost, result->before))) {
    result->verdict = starts.best.converged ? Verdict::kConvergedNotImproved : Verdict::kFailed;
    *reason = "the measure did not decrease; the initial motion is kept";
    return true;
  }
  if (!starts.best.converged) {
    result->verdict = Verdict::kFailed;
    *reason = "no convergence within max_iterations (" + starts.best.message + ")";
  } else {
    result->verdict = Verdict::kConvergedImproved;
  }
  return false;
}

// The measure of `moving` at θ against A, on another thread; A is prepared
// there first if `reference` is still empty (the measure before the motion
// prepares it, the one after reuses it).
std::future<MeasureSummary> MeasureLater(std::unique_ptr<MeasureReference>& reference, const Surface& a,
                                         const Surface& moving, const MeasureOptions& options,
                                         const std::array<double, 6>& theta, const Eigen::Vector3d& centre) {
  // On a thread of its own only when more than one is allowed: --threads=1
  // means one (the measure then runs when its result is asked for).
  const std::launch policy = ExecutionFor(options.threads).parallel() ? std::launch::async : std::launch::deferred;
  return std::async(policy, [&reference, &a, &moving, &options, theta, centre] {
    if (!reference) reference = std::make_unique<MeasureReference>(a, options);
    return Measure(*reference, TransformSurface(moving, RigidOfTheta(theta, centre, a.origin).ToMatrix()),
                   options);
  });
}

// At the solution: the measure after it (beside the standard deviations
// there), the verdict, the standard deviations at the start instead if the
// verdict keeps it, and the motion in every form.
void Finish(const Surface& reference, const Surface& moving, const Level& finest, const Starts& starts,
            const std::array<double, 6>& theta0, const Eigen::Vector3d& centre,
            std::unique_ptr<MeasureReference>& measure_reference, const MeasureOptions& measure_options,
            const AlignOptions& options, const SolveContext& context, AlignResult* result) {
  std::array<double, 6> theta = starts.have_best ? starts.best.theta : theta0;
  // A state of its own only where the solve's cannot serve (built lazily:
  // its normals and vertex sets cost ~2% of a 1e5 alignment).
  std::optional<PairState> own_state;
  auto final_state = [&]() -> PairState& {
    if (!own_state) own_state.emplace(finest.reference, finest.moving, options.max_fold_fraction);
    return *own_state;
  };
  UpdateStats stats;
  // At the volume solve's own state the information is taken there (its
  // surface is B's fixed for the solve); B's own mesh need only be checked
  // for folds then, not re-meshed and located.
  const bool at_solution = starts.best_state != nullptr && starts.best_state->theta() == theta;
  const bool unfolded = at_solution ? OwnMeshFolds(finest.moving, theta, options.max_fold_fraction, &stats)
                                    : final_state().Update(theta, &stats);
  result->folded_triangles = stats.folded;
  result->folded_area_fraction = stats.folded_area_fraction;
  bool failed = !starts.have_best || !unfolded;
  std::string reason = !starts.have_best ? "the solver found no usable solution"
                       : !unfolded       ? "the moving surface folds at the solution"
                                         : "";
  // The measure after the motion runs beside the standard deviations at
  // the solution (needed again only if the verdict keeps the start).
  Information info;
  if (!failed) {
    std::future<MeasureSummary> after =
        MeasureLater(measure_reference, reference, moving, measure_options, theta, centre);
    const Clock::time_point information_start = Clock::now();
    info = StddevAt(at_solution ? *starts.best_state : final_state(), context, options, &result->stddev_source,
                    at_solution ? starts.best_state.get() : nullptr, starts.best_cache.get());
    result->covariance_seconds = Seconds(information_start);
    try {
      result->after = after.get();
    } catch (const InputError& e) {
      failed = true;
      reason = std::string("the surfaces no longer overlap at the solution: ") + e.what();
    }
  }
  const bool information_at_theta = !failed;
  const bool kept = Judge(starts, context.solve_cost, failed, result, &reason);
  if (kept) {
    theta = theta0;
    result->after = result->before;
    final_state().Update(theta, &stats);
  }
  if (kept || !information_at_theta) {
    const Clock::time_point again = Clock::now();
    info = StddevAt(final_state(), context, options, &result->stddev_source);
    result->covariance_seconds = Seconds(again);
  }
  SetStddev(info, options, result, &reason);
  result->verdict_reason = reason;
  SetMotion(theta, centre, finest, reference, result);
}

// `motion_only`: only the solved motion (rotation_vector, translation) and
// a verdict from the solver alone (converged or failed): no measures, no
// information; for the subsample σ's many small alignments.
AlignResult AlignFrom(const Surface& reference, const Surface& moving, const AlignOptions& options,
                      bool motion_only = false) {
  const Clock::time_point start = Clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw InputError("align options: " + error);
  align_steps::CheckPerPointWeights(reference, options);
  const std::array<double, 3> shift = {moving.origin[0] - reference.origin[0], moving.origin[1] - reference.origin[1],
                                       moving.origin[2] - reference.origin[2]};
  const MeasureOptions measure_options = MeasureOptionsFor(options);
  // A prepared once, for the solve and for both measures.
  std::unique_ptr<MeasureReference> measure_reference;
  const std::vector<std::unique_ptr<Level>> levels = align_steps::PrepareLevels(
      reference, moving, options, shift, motion_only ? nullptr : &measure_options,
      motion_only ? nullptr : &measure_reference);
  const Level& finest = *levels.back();
  // The plan, resolved once: the options are read, never written.
  SolveContext context =
      align_steps::MakeContext(&options, align_steps::SparserNodesChosen(finest, options), levels, reference);
  AlignResult result;
  context.log = &result.log;
  result.solve_cost = context.solve_cost == CostKind::kVolume ? "volume"
                      : context.sparser_nodes                 ? "axial at the sparser surface's nodes"
                                                              : "axial";
  const std::array<double, 6> theta0 = InitialTheta(options, finest.moving.centroid, reference.origin);
  align_steps::CheckStart(finest, theta0, moving, &context);
  const Eigen::Vector3d centre = finest.moving.centroid;
  // The measure before the motion is needed only for the verdict: it runs
  // beside the solve, whose prealignment keeps one core busy.
  std::future<MeasureSummary> before;
  if (!motion_only) before = MeasureLater(measure_reference, reference, moving, measure_options, theta0, centre);
  if (options.on_stage) options.on_stage("solving", Seconds(start));
  Starts starts;
  try {
    starts = align_steps::SolveFromStarts(reference, moving, levels, shift, theta0, options, context, start);
  } catch (...) {
    // A measure that failed (e.g. surfaces that do not overlap) is the error
    // to report, not what the solve made of such input.
    if (before.valid()) before.get();
    throw;
  }
  result.iterations = starts.iterations;
  result.remeshes = starts.remeshes;
  result.wide_search_ran = starts.wide_search_ran;
  if (motion_only) {
    const std::array<double, 6> theta = starts.have_best ? starts.best.theta : theta0;
    for (int k = 0; k < 3; ++k) result.rotation_vector[k] = theta[k], result.translation[k] = theta[3 + k];
    result.verdict = starts.have_best && starts.best.converged ? Verdict::kConvergedImproved : Verdict::kFailed;
    result.reference_from_moving = RigidOfTheta(theta, centre, reference.origin);
    result.matrix = result.reference_from_moving.ToMatrix();
    return result;
  }
  result.before = before.get();
  result.termination = starts.have_best ? starts.best.message : "no usable solution";
  if (options.on_stage) options.on_stage("measuring the result", Seconds(start));
  Finish(reference, moving, finest, starts, theta0, centre, measure_reference, measure_options, options, context,
         &result);
  result.seconds = Seconds(start);
  return result;
}

}  // namespace

namespace {

// Align, and the wide search when the verdict asks for it.
AlignResult AlignWithSearch(const Surface& reference, const Surface& moving, const AlignOptions& options) {
  AlignResult result = AlignFrom(reference, moving, options);
  if (options.wide_search != AlignOptions::WideSearch::kAuto || !WideSearchWanted(result, options.cost)) return result;
  const bool poor = result.verdict == Verdict::kFailed || result.verdict == Verdict::kConvergedNotImproved;
  if (options.on_stage) {
    options.on_stage(poor ? "wide search (the first solve did not improve): solving again from many starts"
                          : "wide search (the surfaces are still apart): solving again from many starts",
                     result.seconds);
  }
  AlignOptions wide = options;
  wide.wide_search = AlignOptions::WideSearch::kAlways;
  AlignResult second = AlignFrom(reference, moving, wide);
  second.seconds += result.seconds;
  second.wide_search_ran = result.wide_search_ran = true;
  // Real change between the surfaces also leaves them apart: then the search
  // finds the same minimum, or a worse one, and the first result stays.
  const bool better = second.verdict == Verdict::kConvergedImproved &&
                      (poor || MeasureOfCost(options.cost, second.after) < MeasureOfCost(options.cost, result.after));
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
  sub.initial_reference_from_moving = result->reference_from_moving;
  sub.initial_rotation = sub.initial_translation = {0, 0, 0};
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

AlignResult AlignMotionOnly(const Surface& reference, const Surface& moving, const AlignOptions& options) {
  return AlignFrom(reference, moving, options, /*motion_only=*/true);
}

AlignResult Align(const Surface& reference, const Surface& moving, const AlignOptions& options) {
  if (options.stable.mode == StableOptions::Mode::kAuto) return AlignOnStableTerrain(reference, moving, options);
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
  const Eigen::Matrix4d initial =
      RigidOfTheta(InitialTheta(options, centre_local, reference.origin), centre_local, reference.origin).ToMatrix();
  check.before = ComputeDzStatistics(Measure(reference, TransformSurface(moving, initial, m.threads), m).dz_a, keep);
  check.after = ComputeDzStatistics(Measure(reference, TransformSurface(moving, result.matrix, m.threads), m).dz_a, keep);
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

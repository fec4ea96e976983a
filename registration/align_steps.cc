// The steps of an alignment before its result (align_steps.h).
#include "registration/align_steps.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "measure/input_error.h"
#include "measure/tasks.h"
#include "measure/weights.h"
#include "registration/gap_weight.h"
#include "registration/wide_search.h"

namespace surfreg {
namespace align_steps {
namespace {

// The axial prealignment runs on at most about this many points of each
// surface (AlignOptions::prealign).
constexpr double kPrealignPoints = 5000.0;

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

}  // namespace

void CheckPerPointWeights(const Surface& reference, const AlignOptions& options) {
  if (options.weight != WeightMode::kPerPoint) return;
  // μ lives on the reference's mesh: the reference is fixed, so μ is too.
  const std::string name = reference.source.empty() ? "the reference" : reference.source;
  if (reference.weight.empty()) {
    throw InputError("align: weight per_point needs per-sample weights on the reference, but " + name +
                     " has none");
  }
  const auto positive = [](double w) { return w > 0; };
  if (std::none_of(reference.weight.begin(), reference.weight.end(), positive)) {
    throw InputError("align: weight per_point: every weight of " + name + " is 0");
  }
}

std::optional<ReferenceSide> ReferenceSideOf(const PreparedSurface& prepared) {
  std::optional<ReferenceSide> out;
  if (prepared.mesh->num_duplicates > 0) return out;
  ReferenceSide& side = out.emplace();
  side.xy = *prepared.xy;
  side.z = *prepared.z;
  side.weight = *prepared.weight;
  side.mesh = *prepared.mesh;
  side.tree = *prepared.tree;
  side.hull_area = prepared.hull_area;
  side.domain = prepared.domain->triangles;
  side.domain_vertex = prepared.domain->vertices;
  return out;
}

// density_correction, or 0 (no chord correction, no choice of the sparser
// surface's nodes from it) when either surface's sampling is uneven by
// design (a mesh's vertices: DensitySpread at density_weight or more): the
// correction's model is one area per sample over the whole surface, and
// vertex sets of one mesh share its linear surface instead of cutting
// chords of a smooth one (face pairs sampled at a mesh's vertices, one
// decimated: 0.019° against 2e-5° without it; tests/bench/face_vertex_bench.py).
static double ChordCorrectionRatio(const AlignOptions& options, const ReferenceSide& reference, const MovingSide& moving) {
  if (options.density_weight > 0 &&
      std::max(DensitySpread(reference), DensitySpread(moving)) >= options.density_weight) {
    return 0.0;
  }
  return options.density_correction;
}

// Levels, coarsest first; all share the full cloud's centroid so θ means
// the same motion on every level.
std::vector<std::unique_ptr<Level>> PrepareLevels(const Surface& reference, const Surface& moving,
                                                  const AlignOptions& options,
                                                  const std::array<double, 3>& shift,
                                                  const MeasureOptions* measure_options,
                                                  std::unique_ptr<MeasureReference>* measure_reference) {
  std::vector<std::unique_ptr<Level>> levels;
  for (int l = 0; l < options.levels; ++l) {
    const double keep = options.subsample * std::pow(options.level_factor, -(options.levels - 1 - l));
    auto level = std::make_unique<Level>();
    Level* out = level.get();
    RunBoth(ExecutionFor(options.num_threads), [&] {
      // The measures' preparation of A is the finest level's, by the same
      // domain rule: made once (at 1e5 points 0.08 s).
      std::optional<ReferenceSide> shared;
      if (measure_reference != nullptr && keep >= 1.0) {
        *measure_reference = std::make_unique<MeasureReference>(reference, *measure_options);
        shared = ReferenceSideOf((*measure_reference)->prepared());
      }
      out->reference = shared ? std::move(*shared)
                              : PrepareReference(reference, keep, options.domain,
                                                 ExecutionFor(options.num_threads));  // weights kept per point
      if (options.weight != WeightMode::kPerPoint) out->reference.weight.clear();
      if (options.cost == CostKind::kVolume || options.cost == CostKind::kAuto) {
        ApplySlopeWeight(options.slope_weight, &out->reference);
        ApplyGapWeight(options.gap_weight, &out->reference, ExecutionFor(options.num_threads));
        ApplyDensityWeight(options.density_weight, &out->reference);
      }
    }, [&] { out->moving = PrepareMoving(moving, shift, keep, options.domain, ExecutionFor(options.num_threads)); });
    // After the weights: they are the surface's curvature, which this keeps.
    out->density = CorrectDensityBias(ChordCorrectionRatio(options, out->reference, out->moving),
                                      &out->reference, &out->moving);
    levels.push_back(std::move(level));
  }
  Level& finest = *levels.back();
  // A subsampled finest level has its own centroid; θ keeps meaning a motion
  // about the full cloud's.
  if (options.subsample < 1) finest.moving.centroid = PrepareMoving(moving, shift).centroid;
  for (auto& level : levels) level->moving.centroid = finest.moving.centroid;
  return levels;
}

bool SparserNodesChosen(const Level& finest, const AlignOptions& options) {
  const DensityCorrection& density = finest.density;
  // A density check that ran (share > 0) and found the curvature mixed.
  const bool mixed = density.one_sign_share > 0 && !density.applied;
  return options.cost == CostKind::kAuto && density.ratio >= kSparserNodesRatio && mixed &&
         options.weight != WeightMode::kPerPoint;
}

SolveContext MakeContext(const AlignOptions* options, bool sparser_nodes,
                         const std::vector<std::unique_ptr<Level>>& levels, const Surface& reference) {
  const Level& finest = *levels.back();
  SolveContext context;
  context.options = options;
  context.sparser_nodes = sparser_nodes || options->cost == CostKind::kAxialSparser;
  context.solve_cost =
      context.sparser_nodes || options->cost == CostKind::kAxial ? CostKind::kAxial : CostKind::kVolume;
  if (sparser_nodes) {
    for (const auto& level : levels) level->reference.weight.clear();  // the slope and gap weights
  }
  context.rotation_scale = std::max(RmsRadius(finest.moving), 1e-300);
  if (options->weight == WeightMode::kMask && !options->mask.empty()) {
    // Ω lies within the reference: exclude's enclosing ring need only cover it.
    context.axial.mask = std::make_shared<const MaskRegion>(MakeMaskRegion(
        options->mask, options->mask_mode, {reference.origin[0], reference.origin[1]}, reference.xy));
  }
  context.axial.trim_fraction = options->trim_fraction;
  context.axial.normal_distance = options->normal_distance;
  if (context.solve_cost == CostKind::kAxial && context.sparser_nodes) {
    // finest.density.reference: the reference is the sparser (area per sample).
    (finest.density.reference ? context.axial.moving_nodes : context.axial.reference_nodes) = false;
  }
  return context;
}

// The start must not fold the moving surface; the axial cost's automatic
// loss scale is taken there.
void CheckStart(const Level& finest, const std::array<double, 6>& theta0, const Surface& moving,
                SolveContext* context) {
  const AlignOptions* options = context->options;
  UpdateStats stats;
  const bool loss_scale_wanted =
      context->solve_cost == CostKind::kAxial && options->loss != LossKind::kNone && !(options->loss_scale > 0);
  // Only the loss scale needs B located there (a whole PairState).
  std::optional<PairState> check;
  if (loss_scale_wanted) check.emplace(finest.reference, finest.moving, options->max_fold_fraction);
  if (!(loss_scale_wanted ? check->Update(theta0, &stats)
                          : OwnMeshFolds(finest.moving, theta0, options->max_fold_fraction, &stats))) {
    throw InputError("the initial motion folds " + moving.source + ": " + std::to_string(stats.folded) +
                     " triangles turn over in the xy projection (tilt too large for a height field)");
  }
  if (loss_scale_wanted) {
    context->loss_scale = AutomaticLossScale(*check, context->axial, 1e-9 * context->rotation_scale);
  }
}

// The axial prealignment only has to land in the volume cost's basin: on
// large clouds it runs on a fixed subsample of at most kPrealignPoints of
// each (its time otherwise rivals the volume solve's). Nothing when it runs
// on the coarsest level itself.
//
// Its minimum lies some sample spacings from the volume cost's (at 1e5
// points the first volume step then moves every node: the overlay cache is
// rebuilt from scratch, 0.6 full measures). Where the subsample is at most
// 1/kRefineRatio of the coarsest level, the volume cost is minimized on it
// too (weighted as on the levels) and the level starts there, an
// incremental solve from its first step. Measured (align_bench, 5 runs,
// medians, whole alignment): 1e4 points +15%, 3e4 −8%, 1e5 −6%; the level
// ends at the same minimum.
constexpr double kRefineRatio = 5.0;

Prealignment PrealignSides(const Surface& reference, const Surface& moving,
                           const std::vector<std::unique_ptr<Level>>& levels, const std::array<double, 3>& shift,
                           const AlignOptions& options, CostKind solve_cost) {
  Prealignment out;
  const Level& coarsest = *levels.front();
  const double n_a = static_cast<double>(coarsest.reference.xy.size());
  const double n_b = static_cast<double>(coarsest.moving.points.size());
  const double keep_a = std::min(1.0, kPrealignPoints / n_a), keep_b = std::min(1.0, kPrealignPoints / n_b);
  if (solve_cost != CostKind::kVolume || !options.prealign || std::min(keep_a, keep_b) >= 1) return out;
  const double level_keep = options.subsample * std::pow(options.level_factor, -(options.levels - 1));
  Level& sides = out.sides.emplace();
  RunBoth(ExecutionFor(options.num_threads), [&] {
    sides.reference = PrepareReference(reference, level_keep * keep_a, options.domain);
    if (options.weight != WeightMode::kPerPoint) sides.reference.weight.clear();
  }, [&] { sides.moving = PrepareMoving(moving, shift, level_keep * keep_b, options.domain); });
  sides.density = CorrectDensityBias(ChordCorrectionRatio(options, sides.reference, sides.moving),
                                    &sides.reference, &sides.moving);
  sides.moving.centroid = levels.back()->moving.centroid;
  if (kRefineRatio * static_cast<double>(sides.reference.xy.size()) <= n_a &&
      kRefineRatio * static_cast<double>(sides.moving.points.size()) <= n_b) {
    Level& refine = out.refine.emplace(sides);
    ApplySlopeWeight(options.slope_weight, &refine.reference);
    ApplyGapWeight(options.gap_weight, &refine.reference, ExecutionFor(options.num_threads));
    ApplyDensityWeight(options.density_weight, &refine.reference);
  }
  return out;
}


namespace {

// One start through every level (the prealignment first); false if a level
// gave no usable solution.
// The volume cost's finest state and cache go to `finest_state` and
// `finest_cache`.
bool SolveOneStart(const std::vector<std::unique_ptr<Level>>& levels, const Prealignment& prealign,
                   const AlignOptions& options, std::array<double, 6> theta, SolveContext& context,
                   Clock::time_point start, SolveResult* solved, Starts* starts,
                   std::shared_ptr<PairState>* finest_state, std::shared_ptr<VolumeCostCache>* finest_cache) {
  Eigen::Matrix<double, 6, 6> refined_curvature = Eigen::Matrix<double, 6, 6>::Zero();
  double refined_cost = 0;
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const bool volume = context.solve_cost == CostKind::kVolume;
    const bool keep = volume && l + 1 == levels.size();
    auto state_ptr = std::make_shared<PairState>(levels[l]->reference, levels[l]->moving, options.max_fold_fraction);
    PairState& state = *state_ptr;
    state.set_execution(ExecutionFor(options.num_threads));
    std::shared_ptr<VolumeCostCache> cache;
    if (keep) cache = std::make_shared<VolumeCostCache>(kSolveDirtyFraction, options.cell_kernel);
    context.level = static_cast<int>(l);
    context.seconds_offset = Seconds(start);
    if (volume && options.prealign && l == 0) {
      context.cost = "axial";
      std::optional<PairState> subsampled;  // each start from the sides' own meshes
      if (prealign.sides) {
        subsampled.emplace(prealign.sides->reference, prealign.sides->moving, options.max_fold_fraction);
        subsampled->set_execution(ExecutionFor(options.num_threads));
      }
      context.prealignment = true;
      const SolveResult rough = SolveAxial(subsampled ? *subsampled : state, context, theta);
      context.prealignment = false;
      starts->iterations += std::max(0, rough.iterations);
      if (rough.usable) theta = rough.theta;
      if (prealign.refine) {
        PairState refine(prealign.refine->reference, prealign.refine->moving, options.max_fold_fraction);
        refine.set_execution(ExecutionFor(options.num_threads));
        context.cost = "volume_prealign";
        VolumeWhitening at_solution;
        at_solution.want_final = true;
        const SolveResult refined = SolveVolume(refine, context, theta, nullptr, at_solution);
        starts->iterations += std::max(0, refined.iterations);
        if (refined.usable) theta = refined.theta, refined_curvature = refined.curvature, refined_cost = refined.final_cost;
      }
    }
    // The level starts where the subsample's volume solve ended, whitened by
    // that solve's curvature there, rescaled to this sampling's gaps: its
    // own at 1e5 points costs about five evaluations, the subsample's a
    // twentieth of that.
    VolumeWhitening whitening;
    if (l == 0 && !refined_curvature.isZero()) whitening.given = &refined_curvature, whitening.given_cost = refined_cost;
    context.cost = volume ? "volume" : "axial";
    context.seconds_offset = Seconds(start);
    *solved = volume ? SolveVolume(state, context, theta, cache.get(), whitening) : SolveAxial(state, context, theta);
    starts->iterations += std::max(0, solved->iterations);
    starts->remeshes += state.remeshes();
    if (!solved->usable) return false;
    if (keep) *finest_state = state_ptr, *finest_cache = cache;
    theta = solved->theta;
  }
  return true;
}

}  // namespace

Starts SolveFromStarts(const Surface& reference, const Surface& moving,
                       const std::vector<std::unique_ptr<Level>>& levels, const std::array<double, 3>& shift,
                       const std::array<double, 6>& theta0, const AlignOptions& options, SolveContext& context,
                       Clock::time_point start) {
  Starts starts;
  const Level& finest = *levels.back();
  std::array<double, 6> start_theta = theta0;
  if (options.wide_search == AlignOptions::WideSearch::kAlways) {
    const double keep_a = std::min(1.0, 2000.0 / static_cast<double>(reference.size()));
    const double keep_b = std::min(1.0, 2000.0 / static_cast<double>(moving.size()));
    const ReferenceSide coarse_reference = PrepareReference(reference, keep_a, options.domain);
    MovingSide coarse_moving = PrepareMoving(moving, shift, keep_b, options.domain);
    coarse_moving.centroid = finest.moving.centroid;  // θ: the same motion on every level
    start_theta = WideSearch(coarse_reference, coarse_moving, theta0, options, context.rotation_scale).theta;
    starts.wide_search_ran = true;
  }
  const double spacing = std::sqrt(finest.moving.hull_area / static_cast<double>(finest.moving.points.size()));
  const double start_shift = options.multi_start_shift > 0 ? options.multi_start_shift : 5.0 * spacing;
  const Prealignment prealign = PrealignSides(reference, moving, levels, shift, options, context.solve_cost);
  for (int s = 0; s <= options.multi_start; ++s) {
    context.start = s;
    SolveResult solved;
    std::shared_ptr<PairState> state;
    std::shared_ptr<VolumeCostCache> cache;
    const bool usable = SolveOneStart(levels, prealign, options, Perturbed(start_theta, s, options, start_shift),
                                      context, start, &solved, &starts, &state, &cache);
    if (usable && (!starts.have_best || solved.final_cost < starts.best.final_cost)) {
      starts.best = solved;
      starts.have_best = true;
      starts.best_state = std::move(state);
      starts.best_cache = std::move(cache);
    }
  }
  return starts;
}

}  // namespace align_steps
}  // namespace surfreg

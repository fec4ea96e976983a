#include "registration/align_stable.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <utility>
#include <cstdio>

#include "measure/input_error.h"
#include "measure/mask_region.h"
#include "measure/measures.h"
#include "measure/tasks.h"
#include "registration/align.h"  // Align, TransformSurface: each round is a whole alignment
#include "registration/rigid_consensus.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;


double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The user's μ at each reference sample: 1, its per-point weight, or its
// membership of the mask.
std::vector<double> UserWeights(const Surface& reference, const AlignOptions& options) {
  std::vector<double> weight(reference.size(), 1.0);
  if (options.weight == WeightMode::kPerPoint) {
    weight = reference.weight;
  } else if (options.weight == WeightMode::kMask && !options.mask.empty()) {
    const MaskRegion region =
        MakeMaskRegion(options.mask, options.mask_mode, {reference.origin[0], reference.origin[1]}, reference.xy);
    for (std::size_t i = 0; i < reference.size(); ++i) weight[i] = InsideMask(region, reference.xy[i]) ? 1.0 : 0.0;
  }
  return weight;
}

// The gaps with `moving` at `matrix`: at the reference's samples (NaN
// outside the overlap), their areas, and the moving surface's own gaps
// gathered onto the nearest reference sample.
// The measure of the gaps: the reference without its weights, the node gaps kept.
MeasureOptions GapMeasureOptions(const AlignOptions& options) {
  MeasureOptions m;
  m.domain = options.domain;
  m.keep_node_gaps = true;
  m.threads = options.num_threads;
  return m;
}

// The gaps from `summary`, a measure of `moving` at `matrix` with
// GapMeasureOptions (or one equal to it: uniform weights, the node gaps kept).
GapField GapsOf(const Surface& reference, const Surface& moving, const Eigen::Matrix4d& matrix,
                MeasureSummary summary, const AlignOptions& options) {
  const Surface moved = TransformSurface(moving, matrix, options.num_threads);
  GapField gaps;
  gaps.dz = std::move(summary.dz_a);
  gaps.area = std::move(summary.node_area_a);
  // The nearest reference sample by a bucket grid of about one sample a cell.
  const std::size_t n = reference.size();
  double lo_x = HUGE_VAL, hi_x = -HUGE_VAL, lo_y = HUGE_VAL, hi_y = -HUGE_VAL;
  for (const Point2& p : reference.xy) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x), lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  const double cell = std::max(std::sqrt((hi_x - lo_x) * (hi_y - lo_y) / static_cast<double>(n)), 1e-300);
  const int columns = std::max(1, static_cast<int>((hi_x - lo_x) / cell) + 1);
  const int rows = std::max(1, static_cast<int>((hi_y - lo_y) / cell) + 1);
  auto cell_of = [&](double x, double y, int* c, int* r) {
    *c = std::clamp(static_cast<int>((x - lo_x) / cell), 0, columns - 1);
    *r = std::clamp(static_cast<int>((y - lo_y) / cell), 0, rows - 1);
  };
  std::vector<int32_t> start(static_cast<std::size_t>(columns) * rows + 1, 0), order(n);
  for (const Point2& p : reference.xy) {
    int c, r;
    cell_of(p.x, p.y, &c, &r);
    ++start[static_cast<std::size_t>(r) * columns + c + 1];
  }
  for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    int c, r;
    cell_of(reference.xy[i].x, reference.xy[i].y, &c, &r);
    order[fill[static_cast<std::size_t>(r) * columns + c]++] = static_cast<int32_t>(i);
  }
  gaps.partner_sum.assign(n, 0.0);
  gaps.partner_count.assign(n, 0);
  const double shift_x = moved.origin[0] - reference.origin[0], shift_y = moved.origin[1] - reference.origin[1];
  // Each moving sample's nearest reference sample by chunks, then the sums
  // in the samples' order (the same bits on any thread count).
  std::vector<int32_t> nearest_of(moved.size(), -1);
  const int64_t m = static_cast<int64_t>(moved.size());
  ForEachChunk(ExecutionFor(options.num_threads), m, ChunksFor(m, 4096), [&](int, int64_t first, int64_t last) {
    for (int64_t j = first; j < last; ++j) {
      if (!std::isfinite(summary.dz_b[j])) continue;
      const double x = moved.xy[j].x + shift_x, y = moved.xy[j].y + shift_y;
      int c, r;
      cell_of(x, y, &c, &r);
      int32_t nearest = -1;
      double best = HUGE_VAL;
      for (int ring = 1; ring <= 3 && nearest < 0; ++ring) {
        for (int rr = std::max(0, r - ring); rr <= std::min(rows - 1, r + ring); ++rr) {
          for (int cc = std::max(0, c - ring); cc <= std::min(columns - 1, c + ring); ++cc) {
            const std::size_t b = static_cast<std::size_t>(rr) * columns + cc;
            for (int32_t k = start[b]; k < start[b + 1]; ++k) {
              const int32_t i = order[k];
              const double d = (reference.xy[i].x - x) * (reference.xy[i].x - x) +
                               (reference.xy[i].y - y) * (reference.xy[i].y - y);
              if (d < best) best = d, nearest = i;
            }
          }
        }
      }
      nearest_of[j] = nearest;
    }
  });
  for (std::size_t j = 0; j < moved.size(); ++j) {
    const int32_t nearest = nearest_of[j];
    if (nearest < 0 || !std::isfinite(gaps.dz[nearest])) continue;
    gaps.partner_sum[nearest] += summary.dz_b[j];
    ++gaps.partner_count[nearest];
  }
  return gaps;
}

// `prepared`: the reference without its weights, prepared once for every
// round (MeasureReference: the same summary as measuring it afresh).
GapField GapsAt(const MeasureReference& prepared, const Surface& moving, const Eigen::Matrix4d& matrix,
                const AlignOptions& options) {
  MeasureSummary summary = Measure(prepared, TransformSurface(moving, matrix, options.num_threads), GapMeasureOptions(options));
  return GapsOf(prepared.surface(), moving, matrix, std::move(summary), options);
}

// The node gaps of a measure are many: kept in the result only if asked for.
void DropNodeGaps(MeasureSummary* summary) {
  summary->dz_a = {};
  summary->dz_b = {};
  summary->node_area_a = {};
}

Surface Weighted(const Surface& reference, const std::vector<double>& user, const StableTerrain& stable) {
  Surface out = reference;
  out.weight.resize(reference.size());
  for (std::size_t i = 0; i < reference.size(); ++i) {
    out.weight[i] = stable.flag[i] == kStableSample ? user[i] : 0.0;
  }
  return out;
}

// A later round: from the last motion, the solve only (no search, no σ).
AlignOptions RoundOptions(const AlignOptions& options, const AlignResult& last) {
  AlignOptions o = options;
  o.stable.mode = StableOptions::Mode::kAll;
  o.weight = WeightMode::kPerPoint;
  o.mask.clear();
  o.compute_covariance = false;
  o.stddev_subsamples = 0;
  o.holdout_fraction = 0;
  o.holdout_verdict = false;
  o.wide_search = AlignOptions::WideSearch::kNever;
  o.prealign = false;
  o.levels = 1;
  o.multi_start = 0;
  o.on_stage = nullptr;
  o.initial_reference_from_moving = last.reference_from_moving;
  o.initial_rotation = o.initial_translation = {0, 0, 0};
  return o;
}

int64_t Reclassified(const StableTerrain& a, const StableTerrain& b) {
  int64_t n = 0;
  for (std::size_t i = 0; i < a.flag.size(); ++i) n += (a.flag[i] == kStableSample) != (b.flag[i] == kStableSample);
  return n;
}

// What the first fit (on all of the overlap) was: whether it asks for the
// wide search (WideSearchWanted), because it failed or did not improve
// (rather than leaving the surfaces apart), and its measure.
struct FirstFit {
  bool wanted = false, poor = false;
  double measure = 0;
};

// The first fit's options: on all of the overlap. Under uniform weights
// its measure after it is the gaps' measure (GapMeasureOptions) at its
// motion: kept, not measured again.
AlignOptions FirstFitOptions(const AlignOptions& options) {
  AlignOptions first = options;
  first.stable.mode = StableOptions::Mode::kAll;
  first.keep_node_gaps = options.keep_node_gaps || options.weight == WeightMode::kUniform;
  return first;
}

// The rounds and the final solve (align_stable.h), the wide search as
// `options` say; from `given_first` as the first fit if not null (made with
// FirstFitOptions).
AlignResult FitOnStableTerrain(const Surface& reference, const Surface& moving, const AlignOptions& options,
                               FirstFit* first_fit, AlignResult* given_first = nullptr) {
  const Clock::time_point start = Clock::now();
  const AlignOptions first = FirstFitOptions(options);
  const bool gaps_from_first = options.weight == WeightMode::kUniform;
  // The reference's neighbours and curvature do not depend on the motion:
  // built beside the first fit.
  std::future<SampleAdjacency> adjacency_later =
      std::async(ExecutionFor(options.num_threads).parallel() ? std::launch::async : std::launch::deferred,
                 [&reference, &options] { return MakeSampleAdjacency(reference, ExecutionFor(options.num_threads)); });
  AlignResult result = given_first != nullptr ? std::move(*given_first) : Align(reference, moving, first);
  first_fit->wanted = WideSearchWanted(result, options.cost);
  first_fit->poor = first_fit->wanted && result.verdict != Verdict::kConvergedImproved;
  first_fit->measure = MeasureOfCost(options.cost, result.after);
  // Nothing to classify on:
  if (result.verdict == Verdict::kFailed) {
    if (!options.keep_node_gaps) DropNodeGaps(&result.before), DropNodeGaps(&result.after);
    return result;
  }

  const std::vector<double> user = UserWeights(reference, options);
  std::vector<uint8_t> eligible(reference.size());
  for (std::size_t i = 0; i < eligible.size(); ++i) eligible[i] = user[i] > 0;
  const SampleAdjacency adjacency = adjacency_later.get();
  const StableOptions& rule = options.stable;
  if (options.on_stage) options.on_stage("finding the stable terrain", SecondsSince(start));

  // The first classification on the gaps less the rigid correction most of
  // the overlap agrees on (rigid_consensus.h): the first fit is pulled by
  // what changed, which would blur the change in its gaps.
  const bool sparser = result.solve_cost != "volume" && options.cost == CostKind::kAuto;
  AlignResult last = result;
  // The reference without its weights, prepared for the rounds' measures
  // when the first is needed.
  // (MeasureReference refers to its surface: `plain` outlives it).
  Surface plain;
  std::unique_ptr<MeasureReference> prepared;
  const auto gaps_at = [&](const Eigen::Matrix4d& matrix) {
    if (!prepared) {
      plain = reference;
      plain.weight.clear();
      prepared = std::make_unique<MeasureReference>(plain, GapMeasureOptions(options));
    }
    return GapsAt(*prepared, moving, matrix, options);
  };
  const bool have_gaps = gaps_from_first && result.after.dz_a.size() == reference.size();
  GapField gaps = have_gaps ? GapsOf(reference, moving, result.matrix, result.after, options) : gaps_at(result.matrix);
  if (!options.keep_node_gaps) DropNodeGaps(&result.before), DropNodeGaps(&result.after);
  const ConsensusFit consensus = RigidConsensus(reference, adjacency, gaps.dz, eligible, ExecutionFor(options.num_threads));
  std::vector<double> correction(reference.size(), 0.0);
  for (std::size_t i = 0; i < correction.size(); ++i) {
    if (std::isfinite(consensus.residual[i])) correction[i] = gaps.dz[i] - consensus.residual[i];
  }
  // The same correction at the moving surface's samples gathered there.
  for (std::size_t i = 0; i < correction.size(); ++i) gaps.partner_sum[i] -= correction[i] * gaps.partner_count[i];
  gaps.dz = consensus.residual;
  StableTerrain stable = ClassifyStable(adjacency, gaps, eligible, consensus.flag, rule);
  stable.rounds = 1;
  if (stable.regions == 0) {  // nothing changed: the first fit is the answer
    result.stable = std::move(stable);
    result.seconds = SecondsSince(start);
    return result;
  }
  // Too little left to fit on: keep what the data gave, and say so.
  const int64_t min_samples = std::max<int64_t>(50, (stable.stable_samples + stable.changed_samples) / 20);
  while (stable.rounds < rule.max_rounds && stable.stable_samples >= min_samples) {
    AlignOptions round = RoundOptions(options, last);
    if (sparser) {
      round.cost = CostKind::kAxialSparser;
    }
    AlignResult next = AlignMotionOnly(Weighted(reference, user, stable), moving, round);
    if (next.verdict == Verdict::kFailed) break;
    last = std::move(next);
    gaps = gaps_at(last.matrix);
    StableTerrain again = ClassifyStable(adjacency, gaps, eligible, stable.flag, rule);
    again.rounds = stable.rounds + 1;
    const int64_t moved = Reclassified(stable, again);
    const int64_t total = again.stable_samples + again.changed_samples;
    stable = std::move(again);
    stable.settled = moved <= rule.settle_share * static_cast<double>(total);
    if (stable.settled) break;
  }
  auto warn = [&stable](const std::string& text) {
    stable.warning += (stable.warning.empty() ? "" : "; ") + text;
  };
  if (stable.rounds >= rule.max_rounds && !stable.settled) {
    warn("the stable terrain did not settle in " + std::to_string(stable.rounds) + " rounds");
  }

  if (stable.stable_samples >= min_samples) {
    AlignOptions final_options = options;
    final_options.stable.mode = StableOptions::Mode::kAll;
    final_options.weight = WeightMode::kPerPoint;
    final_options.mask.clear();
    if (sparser) {
      final_options.cost = CostKind::kAxialSparser;
    }
    AlignResult final_result = Align(Weighted(reference, user, stable), moving, final_options);
    if (final_result.verdict != Verdict::kFailed || result.verdict == Verdict::kFailed) {
      result = std::move(final_result);
    } else {
      warn("the fit on the stable terrain failed: the result is the fit on all of the overlap");
    }
  } else {
    warn("too little stable terrain to fit on: the result is the fit on all of the overlap");
  }
  if (stable.stable_share < rule.warn_share) {
    char text[120];
    std::snprintf(text, sizeof text, "only %.0f%% of the overlap is stable terrain", 100 * stable.stable_share);
    warn(text);
  }
  result.stable = std::move(stable);
  result.seconds = SecondsSince(start);
  return result;
}

}  // namespace

AlignResult AlignOnStableTerrain(const Surface& reference, const Surface& moving, const AlignOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("align options: " + error);
  FirstFit first;
  if (options.wide_search != AlignOptions::WideSearch::kAuto) return FitOnStableTerrain(reference, moving, options, &first);
  // A real change leaves the surfaces apart as a wrong minimum does, and
  // wide_search auto's search (1-3 s) then finds the same minimum again. So
  // first without it. Kept: a fit whose own first fit asked for nothing
  // and whose final one asks for nothing either (the search would not have
  // run); or one whose first fit left the surfaces apart but whose fit on
  // the stable terrain lies close on it, with that terrain found without a
  // warning (most of the overlap, settled).
  AlignOptions quick = options;
  quick.wide_search = AlignOptions::WideSearch::kNever;
  AlignResult result = FitOnStableTerrain(reference, moving, quick, &first);
  const bool close = !WideSearchWanted(result, options.cost);
  if (close && (!first.wanted || (!first.poor && result.stable.warning.empty()))) return result;
  if (close && first.wanted && !first.poor) {
    // Only the warning asks for more: the search the first fit would have
    // run, alone. If it finds nothing better, searching first would have
    // kept that first fit, and from it came this very result.
    if (options.on_stage) {
      options.on_stage("the stable terrain is small or did not settle: the wide search from the start",
                       result.seconds);
    }
    AlignOptions wide = FirstFitOptions(options);
    wide.wide_search = AlignOptions::WideSearch::kAlways;
    wide.on_stage = nullptr;
    wide.on_iteration = nullptr;
    // Its motion is what counts here: under block half-samples, their σ
    // only if it goes on from this fit (below).
    const bool own_stddev = wide.stddev_subsamples == 0;
    if (!own_stddev) {
      wide.stddev_subsamples = 0;
      wide.stddev_method = AlignOptions::StddevMethod::kInformation;
    }
    AlignResult searched = Align(reference, moving, wide);
    result.seconds += searched.seconds;
    result.wide_search_ran = true;
    const bool better = searched.verdict == Verdict::kConvergedImproved &&
                        MeasureOfCost(options.cost, searched.after) < first.measure;
    if (!better) return result;
    // As searching first would have gone on: from the search's fit.
    if (options.on_stage) options.on_stage("the wide search found a lower minimum: on from it", result.seconds);
    searched.wide_search_ran = true;
    const double seconds = result.seconds;
    result = FitOnStableTerrain(reference, moving, options, &first, own_stddev ? &searched : nullptr);
    result.seconds += seconds;
    return result;
  }
  // Otherwise all again, searching.
  if (options.on_stage) {
    options.on_stage(first.poor ? "the first fit did not improve: aligning again with the wide search"
                                : "the surfaces are still apart: aligning again with the wide search",
                     result.seconds);
  }
  const double seconds = result.seconds;
  result = FitOnStableTerrain(reference, moving, options, &first);
  result.seconds += seconds;
  return result;
}

}  // namespace surfreg

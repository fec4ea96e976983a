#include "faces/jaw_split.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "faces/jaw_internal.h"
#include "measure/input_error.h"
#include "registration/axial_cost.h"
#include "registration/pair_state.h"
#include "registration/rigid_motion.h"

namespace surfreg {
namespace {

using jaw_internal::Points;

// Every stride-th point (input coordinates), at most kSplitMaxPoints.
Points Strided(const Surface& surface) {
  const std::size_t stride =
      std::max<std::size_t>(1, (surface.size() + kSplitMaxPoints - 1) / kSplitMaxPoints);
  Points points;
  points.reserve(surface.size() / stride + 1);
  for (std::size_t i = 0; i < surface.size(); i += stride) {
    points.push_back({surface.xy[i].x + surface.origin[0], surface.xy[i].y + surface.origin[1],
                      surface.z[i] + surface.origin[2]});
  }
  return points;
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The reference's points (y, |gap|) against one frame.
struct Gaps {
  std::vector<double> y, gap;
  double lower_median = -1;  // median |gap| below the half-height: how far the jaw moved
  double upper_noise = 0;    // robust σ above it: the skull's noise
};

// Frame `points` moved by `reference_from_frame`: the gaps of the whole
// reference's nodes to it (active ones only).
Gaps GapsOf(const Surface& reference, const ReferenceSide& side, const Points& points,
            const Eigen::Matrix4d& reference_from_frame, double half, const JawOptions& options) {
  Gaps gaps;
  const Surface frame = MakeSurface(points, {}, "frame");
  const std::array<double, 3>& origin = reference.origin;
  const std::array<double, 3> shift = {frame.origin[0] - origin[0], frame.origin[1] - origin[1],
                                       frame.origin[2] - origin[2]};
  const MovingSide moving = PrepareMoving(frame, shift);
  PairState state(side, moving, options.max_fold_fraction);
  if (!state.Update(
          ThetaOfRigid(Rigid3d::FromMatrix(reference_from_frame), moving.centroid, origin))) {
    return gaps;  // folds: this frame does not decide
  }
  AxialSettings settings;  // the tracking's gaps, untrimmed, the reference's nodes only
  settings.normal_distance = options.normal_distance;
  settings.moving_nodes = false;
  AxialResiduals residuals;
  ComputeAxialResiduals(state, settings, false, &residuals);
  std::vector<double> lower, upper;
  lower.reserve(side.xy.size());
  upper.reserve(side.xy.size());
  gaps.y.reserve(side.xy.size());
  gaps.gap.reserve(side.xy.size());
  for (std::size_t i = 0; i < side.xy.size(); ++i) {
    if (!residuals.active[i]) continue;
    const double y = side.xy[i].y + origin[1], gap = std::fabs(residuals.r[i]);
    gaps.y.push_back(y);
    gaps.gap.push_back(gap);
    (y < half ? lower : upper).push_back(gap);
  }
  if (!lower.empty() && !upper.empty()) {
    gaps.lower_median = Median(lower);
    gaps.upper_noise = 1.4826 * Median(upper);
  }
  return gaps;
}

// The level with the fewest labels on the wrong side (moving at or above
// it, still below it); of several, the median one. Counts in `search`.
double BestLevel(const Gaps& gaps, double threshold, JawBoundarySearch* search) {
  std::vector<std::size_t> order(gaps.y.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return gaps.y[a] < gaps.y[b]; });
  // Errors with the level below point order[j] (j points below it), for
  // j = 0..n; only levels between distinct y count.
  int moving = 0;
  for (double g : gaps.gap) moving += g > threshold;
  int errors = moving, best = moving;  // j = 0: everything above, every moving point wrong
  std::vector<std::size_t> minima = {0};
  for (std::size_t j = 1; j <= order.size(); ++j) {
    errors += gaps.gap[order[j - 1]] > threshold ? -1 : 1;
    if (j < order.size() && gaps.y[order[j]] == gaps.y[order[j - 1]]) continue;
    if (errors < best) {
      best = errors;
      minima.assign(1, j);
    } else if (errors == best) {
      minima.push_back(j);
    }
  }
  const std::size_t j = minima[minima.size() / 2];
  search->points = static_cast<int>(order.size());
  search->moving_points = moving;
  search->misclassified = best;
  if (order.empty()) return 0.0;
  if (j == 0) return gaps.y[order.front()] - 1.0;
  if (j == order.size()) return gaps.y[order.back()] + 1.0;
  return 0.5 * (gaps.y[order[j - 1]] + gaps.y[order[j]]);
}

std::string Format(const char* format, double a, int b, double c) {
  char text[256];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

}  // namespace

JawBoundary FindJawBoundary(int count, const std::function<Surface(int)>& load,
                            const JawOptions& options, JawBoundarySearch* search_out) {
  using namespace jaw_internal;  // NOLINT: the tracking's pieces
  const auto start = std::chrono::steady_clock::now();
  if (count < 2) throw InputError("jaw: finding the boundary needs at least 2 frames");
  JawBoundarySearch search;
  const Surface reference_frame = load(options.reference);
  ValidateSurface(reference_frame);
  const Points reference_points = Strided(reference_frame);
  double y_lo = reference_points[0][1], y_hi = y_lo;
  for (const auto& p : reference_points) {
    y_lo = std::min(y_lo, p[1]);
    y_hi = std::max(y_hi, p[1]);
  }
  const double half = 0.5 * (y_lo + y_hi);
  // The skull seed: the upper half of the height, as a part of the reference.
  JawBoundary seed_boundary;
  seed_boundary.y_level = half;
  const Split reference_split = SplitFrame(MakeSurface(reference_points, {}, "reference"),
                                           Eigen::Matrix4d::Identity(), seed_boundary);
  ReferencePart seed;
  seed.surface = PartSurface(reference_split.upper, reference_frame.source + " (upper half)",
                             options.min_part_points);
  seed.side = PrepareReference(seed.surface);
  const Surface whole = MakeSurface(reference_points, {}, reference_frame.source);
  const ReferenceSide whole_side = PrepareReference(whole);

  std::vector<Eigen::Matrix4d> skull(count, Eigen::Matrix4d::Identity());
  JawOptions axial = options;  // the skull's motion only decides the gaps: no volume refinement
  axial.cost = JawCost::kAxial;
  Gaps best;
  auto measure = [&](int k, int neighbour) {
    const Surface frame = load(k);
    ValidateSurface(frame);
    const Points points = Strided(frame);
    const Split split =
        SplitFrame(MakeSurface(points, {}, frame.source), skull[neighbour], seed_boundary);
    const Surface part =
        PartSurface(split.upper, frame.source + " (upper half)", options.min_part_points);
    const JawPartResult fit = RegisterPart(seed, part, skull[neighbour], axial, false);
    skull[k] = fit.verdict == Verdict::kFailed ? skull[neighbour] : fit.reference_from_frame;
    Gaps gaps = GapsOf(whole, whole_side, points, skull[k], half, options);
    if (gaps.lower_median > best.lower_median) {
      best = std::move(gaps);
      search.frame = k;
    }
  };
  for (int k = options.reference + 1; k < count; ++k) measure(k, k - 1);
  for (int k = options.reference - 1; k >= 0; --k) measure(k, k + 1);

  const std::string give = "; give boundary_y (or boundary_polygon)";
  if (search.frame < 0) {
    throw InputError(
        "jaw: the upper and lower parts cannot be found: no frame overlaps the reference" + give);
  }
  search.noise = best.upper_noise;
  search.threshold = std::max(kSplitNoiseMultiple * best.upper_noise, 1e-9 * (y_hi - y_lo));
  JawBoundary boundary;
  boundary.margin = options.boundary.margin;
  boundary.y_level = BestLevel(best, search.threshold, &search);
  std::vector<double> below;
  int above = 0;
  for (std::size_t i = 0; i < best.y.size(); ++i) {
    if (best.y[i] < boundary.y_level) {
      below.push_back(best.gap[i]);
    } else {
      ++above;
    }
  }
  search.jaw_gap = below.empty() ? 0.0 : Median(below);
  if (!(search.jaw_gap > search.threshold)) {
    throw InputError(
        Format("jaw: the upper and lower parts cannot be found: no frame moves the lower face "
               "beyond the noise (largest median gap %.3g at frame %d, threshold %.3g)",
               best.lower_median, search.frame, search.threshold) +
        give);
  }
  if (static_cast<int>(below.size()) < options.min_part_points || above < options.min_part_points) {
    throw InputError(
        Format("jaw: the upper and lower parts cannot be found: the level found (y %.6g, from "
               "frame %d) leaves %.0f points on one side",
               boundary.y_level, search.frame,
               static_cast<double>(std::min<int>(static_cast<int>(below.size()), above))) +
        give);
  }
  search.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (search_out != nullptr) *search_out = search;
  return boundary;
}

}  // namespace surfreg

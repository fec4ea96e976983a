#pragma once
// Stable terrain found from the data: which of the reference's samples lie
// on surface that did not change between the two surveys (or, on a face,
// on the part that did not move), so that the alignment fits those only.
//
// The rule (docs/registration.md, "Stable terrain"): at the current motion,
// the vertical gap d at every reference sample in the overlap; its centre m
// (the median over the samples now taken as stable); each sample's scale
// s_i = σ √(n² + g_i²), g_i the interpolation gap the reference's curvature
// predicts there (gap_weight.h CurvatureGaps, at the median spacing; where
// the sampling is uneven by design, a mesh's vertices, scaled by the local
// area per sample over its median), n the noise (1.4826 × MAD of
// d on the flatter half of the stable samples) and σ the robust scale of
// (d − m) / √(n² + g²) on the stable samples, so that curved places, whose
// gaps are larger at the right pose, are not taken for change; a change
// region grows from the samples beyond seed_sigmas × s_i of m, through
// their Delaunay neighbours beyond grow_sigmas × s_i on the same side of m
// (hysteresis: change is a region, its rim below the seed level);
// regions of fewer than min_region_samples samples are noise, not change;
// so is a region where the moving surface's own samples do not see it alike
// (fewer than 3 of them there, or the mean of their gaps not within a
// factor 0.75-1.33 of the reference's, 0.3-1.33 for a region of twice
// min_region_samples or more): the two samplings' interpolation
// error at a curved place has opposite signs at the two surfaces' nodes,
// and where two samplings disagree as data (a fold, a seam) their means
// differ, while change is the same from both;
// the rest, widened by margin_rings rings of neighbours (the rim where the
// change tapers below the grow level), is excluded. Align then fits on the
// rest and classifies again, until the set stops changing.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/surface.h"
#include "measure/tasks.h"

namespace surfreg {

struct StableOptions {
  // auto: find the stable part from the data (the default); all: fit on the
  // whole overlap (the user's mask or weights, if any, still apply).
  enum class Mode { kAll, kAuto };
  Mode mode = Mode::kAuto;
  double seed_sigmas = 4.0;
  double grow_sigmas = 2.0;
  int min_region_samples = 12;
  // Rings of neighbours added around each region: the rim where the change
  // tapers below the grow level (two: the 50% glacier pairs 0.52 / 1.47 ×
  // the oracle's errors, against 1.29 / 2.32 × with one; docs/registration.md).
  int margin_rings = 2;
  int max_rounds = 8;
  // Rounds end when fewer than this share of the overlap's samples changed
  // class since the last one.
  double settle_share = 0.002;
  // A warning when the stable part is below this share of the overlap.
  double warn_share = 0.4;
};
const char* StableModeName(StableOptions::Mode mode);  // "auto" | "all"

// Per reference sample (StableTerrain::flag).
enum StableFlag : uint8_t { kChangedSample = 0, kStableSample = 1, kOutsideOverlap = 2 };

struct StableTerrain {
  bool done = false;         // the automatic classification ran
  std::vector<uint8_t> flag;  // per reference sample, input order (StableFlag)
  double stable_share = 1;   // of the overlap's reference samples (by area when known)
  int64_t stable_samples = 0, changed_samples = 0;
  int regions = 0;           // change regions excluded
  int rounds = 0;            // classifications made
  bool settled = true;       // the last round changed the set by less than settle_share
  double centre = 0;         // m: median gap on the stable part, data units
  double noise_sigma = 0;    // σ n: the gaps' robust scale on the stable part where flat, data units
  std::string warning;       // non-empty: the stable part is small, or did not settle
};

// The gaps a classification reads.
struct GapField {
  std::vector<double> dz;    // at the reference's samples, input order (NaN outside the overlap)
  std::vector<double> area;  // per reference sample (the shares' weights), or empty
  // The moving surface's gaps at its own samples, each added to the nearest
  // reference sample: their sum and count there (both empty: not known).
  std::vector<double> partner_sum;
  std::vector<int32_t> partner_count;
};

// One classification of the reference's samples from their gaps `dz` (NaN
// outside the overlap; reference input order). `eligible[i] == 0` keeps
// sample i out of the stable set whatever its gap (the user's mask or zero
// weight); `stable` (same size, or empty for "all eligible") is the current
// stable set that m and s are measured on. `area` (per sample, or empty)
// weighs the shares. Returns flags and statistics; rounds, settled and
// warning are left to the caller.
StableTerrain ClassifyStable(const Surface& reference, const std::vector<double>& dz,
                             const std::vector<uint8_t>& eligible, const std::vector<uint8_t>& stable,
                             const std::vector<double>& area, const StableOptions& options);

// The same, with the reference's sample adjacency (its Delaunay edges, in
// CSR form) and curvature gaps built once and reused across rounds.
struct SampleAdjacency {
  std::vector<int32_t> offset;  // size n + 1
  std::vector<int32_t> neighbour;
  // g_i, data units (the median curvature where undefined), at the local
  // spacing where the density is uneven by design (stable_terrain.cc).
  std::vector<double> curvature_gap;
  // ∂z/∂x, ∂z/∂y at each sample: the least-squares plane through it and
  // its neighbours (0 where they do not determine one).
  std::vector<std::array<double, 2>> gradient;
};
// Built in chunks of samples on `execution`'s threads: the same on any number.
SampleAdjacency MakeSampleAdjacency(const Surface& reference, const Execution& execution = Execution{1});
StableTerrain ClassifyStable(const SampleAdjacency& adjacency, const GapField& gaps,
                             const std::vector<uint8_t>& eligible, const std::vector<uint8_t>& stable,
                             const StableOptions& options);

}  // namespace surfreg

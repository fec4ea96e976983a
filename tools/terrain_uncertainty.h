#pragma once
// The uncertainty of terrain change for `surfreg align` (README "Terrain"):
// each DEM's vertical standard error from the keys sigma_reference and
// sigma_moving (one number, or a σ raster on that DEM's grid), propagated to
// the DoD at the reference's nodes, thresholded at lod / lod_confidence, and
// the cellwise change budget of measure/change_budget.h.
#include <cstdint>
#include <string>
#include <vector>

#include "measure/change_budget.h"
#include "measure/measures.h"
#include "measure/surface.h"
#include "tools/align_config.h"
#include "tools/io/raster_io.h"
#include "tools/json_writer.h"

namespace surfreg {

// σ at each sample of one input (`key` "reference" or "moving"; the value of
// key sigma_<key>): the number for every sample, or the σ raster's value at
// each sample's cell. A σ raster must be read on the DEM's own grid (same
// window, size and geotransform) and have a finite value >= 0 at each of
// the DEM's valid cells; anything else is an InputError naming the key.
// Empty when the key is not given. `cells`: RasterToSurface's cell of each
// sample (empty for a point cloud, which takes numbers only).
std::vector<double> SigmaPerSample(const AlignConfig& config, const std::string& key,
                                   std::size_t samples, const Raster& grid,
                                   const std::vector<int64_t>& cells);

struct ChangeUncertainty {
  bool active = false;              // some σ was given
  std::vector<double> sigma_dod;    // per reference sample; NaN outside Ω
  std::vector<double> threshold;    // per reference sample: max(lod, t σ_DoD); NaN outside Ω
  ChangeBudget budget;
};

// σ_DoD at the reference's samples after the motion: the reference's own σ
// and the moving DEM's σ interpolated at each reference node on the moved
// surface (linearly, on its mesh, as dz is); then the budget of `after`
// (measured with keep_node_gaps) at lod and lod_confidence. `moved` is the
// moving surface after the motion, in the reference's frame, sample for
// sample as the input; `options` those of `after`.
ChangeUncertainty AnalyseChangeUncertainty(const AlignConfig& config, const Surface& reference,
                                           const Surface& moved, const std::vector<double>& sigma_reference,
                                           const std::vector<double>& sigma_moving,
                                           const MeasureSummary& after, const MeasureOptions& options);

// The budget as JSON (the member `uncertainty` of a `change` object).
JsonObject ChangeUncertaintyJson(const AlignConfig& config, const ChangeUncertainty& u);

// Summary lines for people (no trailing newline), `units` "m" or "data units".
std::string ChangeUncertaintySummary(const AlignConfig& config, const ChangeUncertainty& u,
                                     const std::string& units);

}  // namespace surfreg

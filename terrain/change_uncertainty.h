#pragma once
// The uncertainty of terrain change for `surfreg align` (docs/terrain.md):
// each DEM's vertical standard error from the keys sigma_reference and
// sigma_moving (one number, or a σ raster on that DEM's grid), propagated to
// the DoD at the reference's nodes, thresholded at lod / lod_confidence, and
// the cellwise change budget of terrain/change_budget.h.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "terrain/change_budget.h"
#include "terrain/dod_error.h"
#include "terrain/spatial_budget.h"
#include "measure/measures.h"
#include "measure/surface.h"
#include "terrain/terrain_request.h"
#include "io/raster_io.h"

namespace surfreg {

// σ at each sample of one input (`key` "reference" or "moving"; the value of
// key sigma_<key>): the number for every sample, or the σ raster's value at
// each sample's cell. A σ raster must be read on the DEM's own grid (same
// window, size and geotransform) and have a finite value >= 0 at each of
// the DEM's valid cells; anything else is an InputError naming the key.
// Empty when the key is not given. `cells`: RasterToSurface's cell of each
// sample (empty for a point cloud, which takes numbers only).
std::vector<double> SigmaPerSample(const TerrainRequest& config, const std::string& key,
                                   std::size_t samples, const Raster& grid,
                                   const std::vector<int64_t>& cells);

struct ChangeUncertainty {
  bool active = false;              // some σ was given
  std::vector<double> sigma_dod;    // per reference sample; NaN outside Ω
  std::vector<double> threshold;    // per reference sample: max(lod, t σ_DoD); NaN outside Ω
  std::vector<double> area;         // per reference sample: its area in the budget (0 outside change_mask)
  ChangeBudget budget;
  // error_model variogram: the model fitted on the stable terrain and the
  // budget's ± with the DoD's spatial correlation (terrain/spatial_budget.h;
  // `spatial_block` > 1: the large-region approximation's block of cells).
  std::string error_model = "independent";
  bool spatial = false;
  DodErrorModel model;
  double fill_sigma_spatial = 0, cut_sigma_spatial = 0, net_sigma_spatial = 0;
  int spatial_block = 1;
  // The motion's own uncertainty carried to the budget (AddRegistrationUncertainty):
  // ± one standard error of fill, cut and net from the motion's covariance
  // alone (a registration error shifts every node alike: fully correlated),
  // and combined in quadrature with the DEM errors of the error model
  // (independent, correlated or spatial).
  bool registration = false;
  double fill_sigma_registration = 0, cut_sigma_registration = 0, net_sigma_registration = 0;
  double fill_sigma_total = 0, cut_sigma_total = 0, net_sigma_total = 0;
};

// The rows of a DoD as the propagation reads them (terrain/spatial_budget.h):
// σ (given, or the model's), the threshold max(lod, t σ); with `sums`, the
// nodes of each row met for the first time added to that budget.
BudgetRowReader DodBudgetRows(const GridLayout& grid, const DodBlockReader& read, const DodErrorModel& model,
                              double t, double lod, ChangeBudgetSums* sums);

// The DEM errors' ± of fill, cut and net under the request's error model.
struct ChangeSigmas {
  double fill = 0, cut = 0, net = 0;
};
ChangeSigmas ModelSigmas(const ChangeUncertainty& u);

// Where the reference's samples lie on its raster, for error_model
// variogram: the grid (null for a point cloud) and each sample's cell;
// which samples are stable terrain (empty: all); and which the budget
// counts (empty: all).
struct ReferenceCells {
  const Raster* grid = nullptr;
  const std::vector<int64_t>* cells = nullptr;
  std::vector<bool> stable;
  std::vector<bool> counted;  // the nodes the budget sums over (change_mask); empty: all
};

// σ_DoD at the reference's samples after the motion: the reference's own σ
// and the moving DEM's σ interpolated at each reference node on the moved
// surface (linearly, on its mesh, as dz is), or with error_model variogram
// and no σ given, σ estimated from slope and curvature on the stable
// terrain; then the budget of `after` (measured with keep_node_gaps) at lod
// and lod_confidence, and with error_model variogram its spatially
// correlated ±. `moved` is the moving surface after the motion, in the
// reference's frame, sample for sample as the input; `options` those of
// `after`. InputError (naming error_model) for a variogram of a point cloud
// or of too little stable terrain.
ChangeUncertainty AnalyseChangeUncertainty(const TerrainRequest& config, const Surface& reference,
                                           const Surface& moved, const std::vector<double>& sigma_reference,
                                           const std::vector<double>& sigma_moving,
                                           const MeasureSummary& after, const MeasureOptions& options,
                                           const ReferenceCells& cells = {});

// Adds the registration's share: the derivative of dz at every reference
// node in each of the six motion parameters (central differences of two
// measures each, a step of one standard deviation), summed over the budget's
// gain and loss nodes with their areas into g, and σ² = gᵀ C g for the
// motion's covariance C (AlignResult::covariance, parameters about the
// centroid `centre`, input coordinates). Parameters with zero or undefined
// variance add nothing.
void AddRegistrationUncertainty(const Surface& reference, const Surface& moving,
                                const std::array<double, 3>& rotation_vector,
                                const std::array<double, 3>& translation, const std::array<double, 3>& centre,
                                const Eigen::Matrix<double, 6, 6>& covariance, const MeasureSummary& after,
                                const MeasureOptions& options, ChangeUncertainty* u);

// The empirical variogram of the standardized stable dz with its fit (and
// the fit's two components), as a PNG; lags in `units`. `where` starts the
// errors.
void WriteVariogramPng(const std::string& path, const DodErrorModel& model, const std::string& units,
                       const std::string& where);

// Summary lines for people (no trailing newline), `units` "m" or "data units".
std::string ChangeUncertaintySummary(const TerrainRequest& config, const ChangeUncertainty& u,
                                     const std::string& units);

}  // namespace surfreg

#pragma once
// `surfreg align --max_memory=SIZE`: two DEMs too large to hold, aligned at
// bounded memory (issue 24). The motion is solved on a sample of
// full-resolution patches spread over the reference and the moving data
// around them (terrain/tiled_motion.h), as many samples as the budget holds;
// then the moving DEM is measured after that motion tile by tile, with the
// DoD streamed into its GeoTIFF and dz statistics per tile. Neither DEM is
// ever read whole. Both must be rasters in one projected CRS (or none), or
// both lon/lat on one datum (then aligned in the metric frame an untiled run
// picks: measure_tiled.h OpenTiledPair).
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "measure/measures.h"
#include "registration/align.h"
#include "tools/align_config.h"

namespace surfreg {

// dz after the motion over one tile's reference samples.
struct TileDzRow {
  int64_t tile = 0;
  int32_t column = 0, row = 0, columns = 0, rows = 0;  // the tile's samples
  double x = 0, y = 0;                                 // its centre (input coordinates)
  int64_t count = 0;                                   // samples in the overlap
  double median = 0, nmad = 0, mean = 0, rmse = 0;     // NaN without samples
};

// One sampled patch aligned alone (translation only, from the whole
// motion): where its data says the moving DEM lies against the whole motion.
struct PatchShift {
  int32_t column = 0, row = 0, columns = 0, rows = 0;  // the reference patch
  double x = 0, y = 0;                                 // its centre (input coordinates)
  int64_t reference_samples = 0, moving_samples = 0;
  std::string verdict;            // of its solve ("" when it could not be solved: too little data)
  double dx = 0, dy = 0, dz = 0;  // patch motion − whole motion at its moving centroid
  double sigma_dx = 0, sigma_dy = 0, sigma_dz = 0;  // their standard deviations
  double mean_abs_dz = 0;                           // after its own motion
};

struct TiledAlignReport {
  double budget = 0;  // bytes
  // The sample the motion was solved on.
  int64_t patches = 0;
  int32_t patch = 0;   // side in reference cells
  bool whole = false;  // the pair fitted the budget: the sample is the pair
  int64_t reference_samples = 0, moving_samples = 0;
  // The whole pair after the motion, tile by tile.
  MeasureSummary after;
  int32_t tile = 0;
  int64_t tiles = 0;
  std::vector<TileDzRow> tile_rows;
  std::vector<PatchShift> patch_shifts;  // with config.terrain.patch_shifts
  int64_t dz_count = 0;
  double dz_mean = 0, dz_rmse = 0;  // over every reference sample in the overlap
  double cell_size = 0;             // the reference's, for errors in cells
  bool known = false;               // config.terrain.known_matrix given
  double rotation_error_deg = 0, translation_error = 0;
};

// The DoD after the motion in blocks of f × f reference cells (their mean),
// gathered tile by tile: what `dod_png` draws of a DoD never held whole.
// With a threshold (lod, or the budget's), change within it counts as 0.
struct DodOverview {
  int32_t factor = 1;
  int32_t columns = 0, rows = 0;
  std::vector<double> sum;
  std::vector<int32_t> count;
  std::array<double, 6> geotransform{};  // the reference's
  bool thresholded = false;
  bool metric = false;   // dz in metres (a projected CRS in metres, or lon/lat DEMs' frame)
  bool degrees = false;  // a lon/lat grid
};

struct TiledAlignRun {
  AlignResult result;  // its before/after measures are the sample's
  TiledAlignReport report;
  std::string json;  // the transform JSON with a "tiled" member
  DodOverview overview;  // with config.terrain.dod_png
};

// Draws the overview as config.terrain.dod_png (the untiled run's map).
void WriteDodOverviewPng(const AlignConfig& config, const DodOverview& overview);

// Throws InputError (naming the key) for what a tiled alignment does not
// take: inputs that are not two rasters in one projected CRS, a window,
// per-point weights or a mask raster, and the outputs that need the whole
// surfaces (aligned, histogram_png, change_csv, σ rasters). The DEMs' σ as numbers
// give the whole pair's change budget (σ rasters are refused).
void CheckTiledAlign(const AlignConfig& config);

// The run above; writes the DoD (dod) tile row by tile row and nothing else
// (the caller writes output, matrix_txt and log; TileStatsCsv and PatchShiftsCsv the CSVs).
// `on_iteration` sees every solver iteration.
TiledAlignRun AlignRasterTiles(
    const AlignConfig& config,
    const std::function<void(const AlignOptions::Iteration&)>& on_iteration);

// tile,column,row,columns,rows,x,y,samples,dz_median,dz_nmad,dz_mean,dz_rmse.
std::string TileStatsCsv(const std::vector<TileDzRow>& rows);

// patch,column,row,columns,rows,x,y,reference_samples,moving_samples,verdict,
// dx,dy,dz,sigma_dx,sigma_dy,sigma_dz,mean_abs_dz.
std::string PatchShiftsCsv(const std::vector<PatchShift>& rows);

// The lines the CLI prints after the alignment's own summary.
std::string TiledAlignSummary(const TiledAlignReport& report);

}  // namespace surfreg

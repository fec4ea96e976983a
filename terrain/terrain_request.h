#pragma once
// What a terrain run is asked (docs/terrain.md): the two inputs and how they
// are read, the alignment's options, and the change it reports: rasters,
// CRSs and the metric frame, the level of detection, the DEMs' σ, the stable
// terrain, and the rasters, tables and figures it writes. The CLI fills it
// from the align and measure keys (tools/align_config.h, whose AlignConfig
// adds the command's own outputs); a C++ client sets the fields.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "registration/align_options.h"
#include "io/surface_reader.h"

namespace surfreg {

// Terrain: rasters, geographic frames, change detection (docs/terrain.md).
struct TerrainSettings {
  std::string reference_crs, moving_crs;  // "" = the raster's own, or none
  std::string frame = "auto";             // auto | enu | utm (geographic inputs)
  int band = 1;                           // raster band
  std::array<int, 4> window = {0, 0, 0, 0};  // column, row, columns, rows; 0 = all
  double lod = 0;                         // level of detection for cut/fill (data units)
  std::string dod;                        // DoD GeoTIFF on the reference raster's grid
  std::string dod_png, histogram_png;     // figures
  std::string change_csv;                 // dz at every reference sample before/after
  std::vector<double> known_matrix;       // 16 numbers (moving -> reference) or empty
  std::string mask_raster;                // stable terrain raster (non-zero cells) as μ; "" = none
  // Each DEM's vertical standard error: a number >= 0 (data units) or a σ
  // raster on that DEM's grid; "" = none (terrain/change_budget.h).
  std::string sigma_reference, sigma_moving;
  double lod_confidence = 0;              // (0, 1): threshold t(confidence) · σ_DoD; 0 = none
  // The budget's ± (terrain/change_uncertainty.h): "independent" or
  // "correlated" cells, or "variogram": σ and the spatial correlation
  // estimated on the stable terrain (terrain/dod_error.h).
  std::string error_model = "independent";
  std::string variogram_png;              // the variogram with its fit
  // Polygons (a mask file) over which the change budget is summed; "" = the whole overlap.
  std::string change_mask;
  std::string dod_sigma, dod_thresholded;  // GeoTIFFs on the reference raster's grid
  // Two DEMs too large to hold (tools/align_tiled.h): a memory budget such
  // as "2G" ("" = untiled), and the per-tile dz statistics CSV.
  std::string max_memory;
  std::string tile_stats;
  std::string patch_shifts;  // each sampled patch's own shift (CSV); "" = none
  // Whether any terrain output or setting is asked for (or an input is a
  // raster or LAS): then `align` also reports change and dz statistics.
  bool Active(const std::string& reference, const std::string& moving) const;
};

struct TerrainRequest {
  std::string reference;  // fixed surface file (required)
  std::string moving;     // surface file moved onto the reference (required)
  // The alignment's settings; the change is measured on its domain and its
  // stable terrain. initial_rotation is in radians here; weight and mask
  // are set from `mask` and `per_point_weights` (FinishAlignConfig).
  AlignOptions options;
  std::string mask;          // polygon file (input coordinates) for μ; "" = uniform
  std::string mask_layer;    // a vector mask's layer; "" = the first
  std::string mask_crs_wkt;  // the mask file's CRS ("" = the reference's)
  bool per_point_weights = false;  // the reference's sample weights as μ
  // A start as a 4x4 matrix (16 numbers, row-major, moving -> reference,
  // input coordinates); empty = none.
  std::vector<double> initial_matrix;
  // How point files are read (ReadOptions, io/surface_reader.h).
  std::vector<int> classes;          // LAS classifications kept; empty = all
  std::vector<std::string> columns;  // text clouds: x, y, z [, weight] columns; empty = 3 or 4
  TerrainSettings terrain;
  // Where each key was last set: "t.yaml:3: key 'cost'", "flag '--cost'",
  // "argument MOVING". Keys left at their default are absent.
  std::map<std::string, std::string> origin;

  // origin[key], or "key 'KEY'" for a default: the start of a message.
  std::string Where(const std::string& key) const;
  // Whether `key` was given (is in `origin`).
  bool Given(const std::string& key) const { return origin.count(key) != 0; }
};

// request.reference or request.moving (`key` "reference" or "moving").
const std::string& InputPath(const TerrainRequest& request, const std::string& key);

// How request.reference or request.moving (`key`) is read: `classes` if it
// is LAS or the other input is not, `columns` if it is a text cloud or the
// other is not (so a key that fits neither input is refused, by the reader).
ReadOptions InputReadOptions(const TerrainRequest& request, const std::string& key);

// Reads request.reference or request.moving (`key`) with its classes and
// columns; a read error is prefixed with where the key was set (and names
// `classes` or `columns` when one of them was refused). A non-null `crs`
// gets the file's CRS text (see ReadSurface).
Surface ReadInput(const TerrainRequest& request, const std::string& key, std::string* crs = nullptr);

}  // namespace surfreg

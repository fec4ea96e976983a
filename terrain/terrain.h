#pragma once
// Terrain co-registration around `surfreg align` (docs/terrain.md): reading
// DEM rasters and point clouds into one metric frame, and after the
// alignment the change between the surveys: the DoD on the reference grid,
// cut/fill beyond a level of detection, dz statistics on stable terrain
// before and after, and the figures.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "measure/dz_statistics.h"
#include "measure/measures.h"
#include "registration/align.h"
#include "terrain/geo_frame.h"
#include "io/plot.h"
#include "io/raster_io.h"
#include "terrain/change_uncertainty.h"
#include "terrain/terrain_request.h"

namespace surfreg {

struct TerrainInputs {
  Surface reference, moving;  // in `frame` (metric), ready for Align
  Crs reference_crs, moving_crs;
  GeoFrame frame;
  // The reference raster's grid (values dropped) and the cell of each
  // reference sample, when the reference is a raster: for the DoD.
  bool reference_is_raster = false;
  Raster reference_grid;
  std::vector<int64_t> reference_cells;
  double cell_size = 0;                      // reference raster's (mean) cell size, or 0
  std::array<double, 3> moving_centroid_input = {0, 0, 0};  // in the reference CRS (lon/lat/h if geographic)
  // Each DEM's vertical standard error per sample (keys sigma_reference,
  // sigma_moving; terrain/change_uncertainty.h); empty = not given.
  std::vector<double> sigma_reference, sigma_moving;
  // The moving input's CRS when it was not the reference's and the moving
  // samples were reprojected into the reference's CRS; "" otherwise.
  std::string moving_reprojected_from;
  // Compact rasters (ReadTerrainInputs' `compact`): both inputs rasters
  // kept whole, heights and all (reference_grid, moving_grid), for
  // MeasureRasterPair about `raster_origin`; `reference`, `moving`,
  // `reference_cells` and `moving_centroid_input` are then not made
  // (ExpandCompactRasters makes them).
  bool compact = false;
  Raster moving_grid;
  std::array<double, 3> raster_origin = {0, 0, 0};
};

// A file's CRS and the one a key gives (`key_text`, "" = none given): the
// key's when the file has none; both given must agree (InputError naming
// `key_where` and `path`).
Crs ResolveCrs(const Crs& from_file, const std::string& key_text, const std::string& key_where,
               const std::string& path);

// A map of `values` (row-major, one per cell of `grid`) over the grid's
// extent, for WriteMapPng.
GridField MapFieldOn(const Raster& grid, std::vector<double> values);

// The unit of lengths in the inputs' frame, for summaries: "m" in a metric
// frame (UTM, ENU) or a metre CRS, "ft" in a foot CRS, else "units".
std::string LengthUnit(const TerrainInputs& inputs);

// Reads both inputs of `config` (rasters with the band and window of
// config.terrain, point files as ReadSurface does), resolves their CRSs
// (the raster's own, or reference_crs / moving_crs; a key overrides a file
// that has none, and must agree with one that has) and brings both into one
// metric frame. Errors name the key or file. A non-null `reference` or
// `moving` is used instead of reading that file (samples already in memory,
// e.g. the Python module's arrays: no CRS of their own, the keys' apply).
// `tiled_origin`: two rasters read from files both take the origin of the
// reference's extent (RasterOrigin), as a tiled measure gives them, so that
// the untiled measure computes with the very same doubles (its DoD is then
// the tiled one to the bit). The two files are read side by side on two
// threads unless `threads` (default: the config's) is 1; the result is the
// same, and of two bad inputs the reference's error is the one reported.
// `compact` (with `tiled_origin`, two raster files): when the pair needs
// nothing but their heights on their grids (one CRS or none, so no
// reprojection or change of frame; no σ and no mask raster), the rasters
// are kept whole instead of made into surfaces (TerrainInputs::compact).
TerrainInputs ReadTerrainInputs(const TerrainRequest& config, const Surface* reference = nullptr,
                                const Surface* moving = nullptr, bool tiled_origin = false,
                                std::optional<int> threads = std::nullopt, bool compact = false);

// Makes the surfaces of compact inputs, as ReadTerrainInputs makes them
// for two rasters (the same samples, origin and errors); a no-op otherwise.
void ExpandCompactRasters(const TerrainRequest& config, TerrainInputs* inputs);

// Mask rings given in the mask file's CRS (`mask_crs_wkt`; "" = the
// reference's) into the frame `in` works in: reprojected into the
// reference's CRS when both have one and they differ, then moved as the
// reference was (PointsToFrame). `where` starts the errors.
void MaskToFrame(const TerrainInputs& in, const std::string& mask_crs_wkt, const std::string& where,
                 std::vector<MaskRing>* rings);

// The reference's samples inside the polygons of config.terrain.change_mask
// (read with ReadMask, brought into the frame as MaskToFrame does): the
// nodes the change budget sums over. Empty when no change_mask is given.
std::vector<bool> ChangeMaskNodes(const TerrainRequest& config, const TerrainInputs& in);

struct TerrainReport {
  MeasureSummary before, after;     // with change detection and node gaps
  // Per reference sample: inside the mask (all if none) and, with stable
  // auto, on the stable terrain the alignment found.
  std::vector<bool> stable;
  DzStatistics stable_before, stable_after;
  GeographicOffset offset;          // the moving centroid's shift on the ground
  double spacing = 0;               // cell size, or mean sample spacing sqrt(area / n)
  bool known = false;               // errors against config.terrain.known_matrix
  double rotation_error_deg = 0, translation_error = 0;  // at the moving centroid
  std::array<double, 3> known_translation = {0, 0, 0};   // the truth's shift of the centroid
  ChangeUncertainty uncertainty;    // with sigma_reference / sigma_moving
  // The level of detection of cut/fill and where it came from: the key
  // `lod`, or when that is not given (and no lod_confidence),
  // kAutoLodSigmas × the NMAD of dz on the stable terrain after the
  // alignment (the DoD's own noise there; 1.96: 95% for Gaussian dz).
  double lod = 0;
  std::string lod_source;
};
inline constexpr double kAutoLodSigmas = 1.96;

// The error of `matrix` against config.terrain.known_matrix (16 numbers,
// moving -> reference): the angle of the rotations' difference, and the
// distance between where the two matrices take the moving centroid
// `centroid` (input coordinates).
struct KnownMotionError {
  double rotation_deg = 0, translation = 0;
};
KnownMotionError ErrorAgainstKnown(const Eigen::Matrix4d& matrix, const std::vector<double>& known,
                                   const Eigen::Vector3d& centroid);


// The change before and after `result` (measures with config.terrain.lod,
// the mask of config.options as stable terrain), and the errors against a
// known matrix.
TerrainReport AnalyseTerrain(const TerrainRequest& config, const TerrainInputs& inputs,
                             const AlignResult& result);

// Writes the DoD GeoTIFF, the change CSV and the figures that config asks
// for (each atomically).
void WriteTerrainOutputs(const TerrainRequest& config, const TerrainInputs& inputs,
                         const TerrainReport& report);

// The summary lines for people (no trailing newline on the last).
std::string TerrainSummary(const TerrainRequest& config, const TerrainInputs& inputs,
                           const TerrainReport& report);

}  // namespace surfreg

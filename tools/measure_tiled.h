#pragma once
// `surfreg measure --tile=N` / `--max_memory=SIZE`: two DEMs measured tile by
// tile (terrain/tiled_measure.h), each tile read as a window of the rasters
// (GDAL block reads), so memory is bounded by the tile, not the rasters. The
// result equals the untiled measure (to 1e-9 relative for volumes and
// areas). Both DEMs are in one projected CRS (or both have none), or both
// lon/lat on one datum (moved into the untiled run's metric frame window by
// window: OpenTiledPair).
#include <cstdint>
#include <functional>
#include <string>

#include "measure/measures.h"
#include "terrain/tiled_measure.h"
#include "terrain/tiled_motion.h"
#include "tools/align_config.h"
#include "terrain/geo_frame.h"
#include "tools/measure_parts.h"
#include "terrain/change_uncertainty.h"

namespace surfreg {

// A tiled measure in parts (tools/measure_parts.h): shard K of N, its
// partial's path, and whether to resume an interrupted run. Every tiled run
// keeps its state in a directory (StateDirectory) while it runs: the state
// after each tile row (state.json) and the DoD of the rows done
// (dod_row_<tile row>.tif), removed once the outputs are written.
struct TiledParts {
  int32_t shard = 1, shards = 1;
  std::string partial;   // --partial=P.json ("" = none)
  bool resume = false;   // --resume
  std::string settings;  // the inputs and settings, equal in every part and on resume
  // false (MeasureSurfaces without parts, the tiled alignment): no state
  // kept for a resume; the DoD rows go to a directory of this process's,
  // removed in any case.
  bool checkpoint = true;
};

// The parts settings as `measure` takes them: `shard` "K/N" ("" = 1/1),
// the partial's path ("" = none; a name ending in .json, required for a
// shard) and resume. `where(key)` starts the messages ("flag '--shard'",
// "keyword 'shard'"); `partial_hint` shows how to give a partial
// ("--partial=P.json"). Throws InputError.
TiledParts TiledPartsOf(const std::string& shard, const std::string& partial, bool resume,
                        const std::function<std::string(const std::string&)>& where,
                        const std::string& partial_hint);

// Where a tiled run keeps its state: P.json.resume/ with a partial, else
// DOD.tif.resume/ with a DoD, else surfreg-measure-<hash of the settings>.resume/
// in the current directory.
std::string StateDirectory(const std::string& dod, const TiledParts& parts);

// What tiling needs of one raster: its size and geotransform (read from its
// first row and column, not its values) and its CRS.
struct RasterShape {
  int32_t columns = 0, rows = 0;
  std::array<double, 6> geotransform{};
  Crs crs;
};

// The shape of the raster config names under `key` ("reference" or
// "moving"), its CRS resolved with the key's _crs setting.
RasterShape ReadRasterShape(const AlignConfig& config, const std::string& key);

// The raster at `path` (band `band`, shape `shape`) read a window at a time
// through GDAL, with the samples relative to `origin`.
TiledRasterSource RasterTileSource(const std::string& path, int band, const RasterShape& shape,
                                   const std::array<double, 3>& origin);

// The two DEMs of `config` as tiled sources in one metric frame, with the
// frame and CRS checks of an untiled run. Projected (or CRS-less) DEMs stay
// as given, with one origin, the centre of A's extent. Two lon/lat DEMs on
// one datum are moved sample by sample into the frame an untiled run picks
// (config.terrain.frame: UTM, or ENU about their centre), found from one
// pass over each DEM's valid samples; a window is found back through the
// inverse map. `where` names the setting that asked for tiles.
struct TiledPair {
  RasterShape a, b;
  GeoFrame frame;
  std::array<double, 3> origin{};  // in the frame
  TiledRasterSource source_a, source_b;
};
TiledPair OpenTiledPair(const AlignConfig& config, const std::string& where);

// The moving raster measured after a rigid motion (terrain/tiled_motion.h):
// the matrix in the rasters' coordinates and the range of its heights.
struct MovedRaster {
  RowMajorMatrix4 matrix = kIdentityMatrix4;
  double z_min = 0, z_max = 0;
};

// A tiled measure's change budget (terrain/change_budget.h): both DEMs' σ
// given as numbers (a σ raster is not tiled yet), so one σ_DoD for every
// node. Active only when config gives a σ; throws InputError naming the
// key of a σ raster.
struct TiledBudget {
  bool active = false;
  double sigma_dod = 0, threshold = 0, t = 0;
};
TiledBudget TiledBudgetOf(const AlignConfig& config, double level_of_detection, const std::string& where);

// The change uncertainty of a whole tiled run's state (its budget sums;
// inactive without a budget): as AnalyseChangeUncertainty gives it untiled.
ChangeUncertainty TiledChangeUncertainty(const TiledPartial& whole, const AlignConfig& config);

struct TiledMeasureRun {
  MeasureSummary summary;  // a whole run's (shards == 1)
  TiledPartial part;       // the part measured (the whole run for 1 of 1)
  DodBand dod;             // the DoD written (a band for a shard); path "" without
  std::string state;       // the state directory, to remove once the outputs are written
  Crs crs_a, crs_b;
  GeoFrame frame;  // the rasters' coordinates as given
  int32_t tile = 0;
  int64_t tiles = 0;
};

// Measures config.moving against config.reference (two raster files, band
// config.terrain.band) in tiles of `tile` reference cells with `options`
// (uniform or mask weights; the mask in the rasters' CRS). `where` names the
// setting that asked for tiles, for the messages of what cannot be tiled.
// A mask (options.mask) is brought from its file's CRS (`mask_crs_wkt`, ""
// = A's) into A's, as an untiled measure does.
// With config.terrain.dod, the DoD (B − A at A's cells, nodata outside Ω)
// is written tile by tile into GeoTIFFs of a tile row each, never held
// whole, then joined into that GeoTIFF on A's grid (a shard's: its band of
// rows, all final but its first, which the merge settles). With `moved`,
// the moving raster is measured after that motion; `on_tile` (may be empty)
// sees each tile's DoD as it is done.
TiledMeasureRun MeasureRasterTiles(const AlignConfig& config, MeasureOptions options,
                                   const std::string& mask_crs_wkt, const std::string& mask_where,
                                   int32_t tile, const std::string& where, const TiledParts& parts,
                                   const std::function<void(const TiledProgress&)>& on_progress,
                                   const MovedRaster* moved = nullptr,
                                   const std::function<void(const TileDod&)>& on_tile = nullptr,
                                   const TiledBudget& budget = {});

}  // namespace surfreg

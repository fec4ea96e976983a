#pragma once
// `surfreg measure --tile=N` / `--max_memory=SIZE`: two DEMs measured tile by
// tile (measure/tiled_measure.h), each tile read as a window of the rasters
// (GDAL block reads), so memory is bounded by the tile, not the rasters. The
// result equals the untiled measure (to 1e-9 relative for volumes and
// areas). For now both DEMs must be in one projected CRS (or both have
// none): a geographic pair's change of frame is not tiled yet.
#include <cstdint>
#include <functional>
#include <string>

#include "measure/measures.h"
#include "measure/tiled_measure.h"
#include "tools/align_config.h"
#include "tools/geo_frame.h"

namespace surfreg {

// Bytes a tile of side `tile` (cells) takes while measured: both windows,
// their meshes and the overlay (about 700 bytes per reference cell, measured
// on the tests' pairs), and the tile side that fits in `bytes`.
double TileBytes(int32_t tile);
int32_t TileForMemory(double bytes);

// Parses a memory size: "512M", "2G", "1.5GiB", "800000000" (bytes).
// Throws InputError starting with `where`.
double ParseMemorySize(const std::string& text, const std::string& where);

struct TiledMeasureRun {
  MeasureSummary summary;
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
// is written tile by tile into that GeoTIFF on A's grid, never held whole.
TiledMeasureRun MeasureRasterTiles(const AlignConfig& config, MeasureOptions options,
                                   const std::string& mask_crs_wkt, const std::string& mask_where,
                                   int32_t tile, const std::string& where,
                                   const std::function<void(const TiledProgress&)>& on_progress);

}  // namespace surfreg

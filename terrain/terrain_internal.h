#pragma once
// Pieces of the terrain reader shared by terrain.cc and terrain_rasters.cc.
// Internal: not installed.
#include <array>
#include <optional>
#include <string>

#include "io/raster_io.h"
#include "measure/surface.h"
#include "measure/tasks.h"
#include "terrain/terrain.h"

namespace surfreg {
namespace terrain_internal {

// The raster of input `key` (its band and window), read on `threads`
// (raster_io.h); errors without the key.
Raster ReadInputRaster(const TerrainRequest& config, const std::string& key, int threads = 1);

// The mean of a surface's samples in input coordinates.
std::array<double, 3> CentroidInput(const Surface& s);

// Cell size in metres (geographic grids: degrees at the grid's latitude).
double CellSize(const Raster& grid, const Crs& crs);

// Both raster inputs read side by side (of two bad ones, the reference's
// error is the one thrown, named by its key as ReadTerrainInputs names it).
// When the pair is one ReadTerrainInputs' `compact` keeps whole (one CRS or
// none, no σ, no mask raster), fills *inputs as compact and returns true;
// otherwise leaves the rasters read in *reference and *moving for the
// general path and returns false.
bool ReadCompactRasters(const TerrainRequest& config, const Execution& execution,
                        TerrainInputs* inputs, std::optional<Raster>* reference,
                        std::optional<Raster>* moving);

}  // namespace terrain_internal
}  // namespace surfreg

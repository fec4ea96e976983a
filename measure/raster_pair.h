#pragma once
// Two rasters on one grid, or on one lattice offset by a fraction of a
// cell, measured from their heights alone (issue 47): the compact form of
// grid_pair.h's measures for DEMs read from files. No per-sample positions,
// cells, index or mesh are built: a raster's cells are its own index, a
// position is its geotransform at the cell, and a cell is complete when its
// four corner heights are valid.
//
// The result is the one Measure gives for the two rasters' samples (each
// valid cell's centre about `origin`, in row-major order, as the terrain
// reader makes them, terrain/tiled_measure.h RasterBlockToSurface): on one
// grid the same cells and nodes, each triangle's integrals from the same
// doubles in the same chunks (the same bits); offset, the same sweep as
// grid_sweep.cc's, to rounding. The hulls' areas come from the lattice's
// cell area.
#include <array>
#include <cstdint>
#include <string>

#include "measure/measures.h"

namespace surfreg {

// One raster as the measure reads it.
struct RasterHeights {
  const double* z = nullptr;  // columns * rows heights, row-major, row 0 first; NaN = nodata
  int64_t columns = 0, rows = 0;
  // GDAL's: cell (c, r) is centred at (g0 + (c + ½) g1 + (r + ½) g2, g3 + (c + ½) g4 + (r + ½) g5).
  std::array<double, 6> geotransform = {0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  std::string source;  // for messages, as Surface::source
};

// B against A, both about `origin` (input coordinates subtracted from every
// position and height, as Surface::origin), into *out as Measure would
// fill it, with keep_node_gaps: dz_a in A's row-major order of valid cells;
// with `all_node_outputs` also node_area_a, and dz_b on offset lattices (on
// one grid every node of B in Ω is one of A's: dz_b is left empty). True
// when this path applies: the same cell vectors; B's cells a whole number
// of A's cells away with every position both have equal, or a fraction of
// a cell that puts no node on the other's lattice lines; both rasters with a
// complete cell; heights within kMaxCoordinate; the options the grid paths
// compute with uniform weights (overlay volume, the data domain, uniform
// μ); an overlap Measure accepts. False otherwise, with *out untouched:
// Measure on the rasters' samples then gives the answer or the error.
bool MeasureRasterPair(const RasterHeights& a, const RasterHeights& b,
                       const std::array<double, 3>& origin, const MeasureOptions& options,
                       MeasureSummary* out, bool all_node_outputs = true);

}  // namespace surfreg

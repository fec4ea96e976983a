#pragma once
// One raster of a pair measured from its heights alone (raster_pair.h):
// its cells' validity and completeness, positions as the terrain reader
// makes them, its box of valid cells and its samples' numbering; the
// domain's and hull's areas and the node areas, each summed as the one-grid
// path sums them (grid_cells.h). Internal, for raster_pair.cc and
// raster_sweep.cc.
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "measure/grid_cells.h"
#include "measure/raster_pair.h"
#include "measure/tasks.h"

namespace surfreg {
namespace raster_sides {

// One raster's cells: validity, positions (RasterBlockToSurface's doubles)
// and its box of valid cells.
struct Side {
  const RasterHeights* raster = nullptr;
  Point2 origin;                                     // subtracted from positions
  double z_origin = 0.0;                             // subtracted from heights
  int64_t c_lo = 0, c_hi = -1, r_lo = 0, r_hi = -1;  // the box of valid cells (empty: c_hi < c_lo)
  std::vector<int64_t> row_start;  // valid cells before each row: the sample numbering
  std::vector<std::array<int64_t, 2>>
      row_ends;  // each row's first and last valid column (-1: none)
  int64_t samples = 0;

  bool Valid(int64_t c, int64_t r) const {
    return c >= 0 && r >= 0 && c < raster->columns && r < raster->rows &&
           std::isfinite(raster->z[static_cast<std::size_t>(r * raster->columns + c)]);
  }
  double Z(int64_t c, int64_t r) const {
    return raster->z[static_cast<std::size_t>(r * raster->columns + c)] - z_origin;
  }
  Point2 Xy(int64_t c, int64_t r) const {
    const auto& g = raster->geotransform;
    const double cc = static_cast<double>(c) + 0.5, rr = static_cast<double>(r) + 0.5;
    return {g[0] + cc * g[1] + rr * g[2] - origin.x, g[3] + cc * g[4] + rr * g[5] - origin.y};
  }
  // Cells (c, r) of row r, c in [0, columns): complete when the corners
  // (c, r) (c+1, r) (c+1, r+1) (c, r+1) are valid; 0 outside the raster.
  void CompleteRow(int64_t r, uint8_t* out) const {
    const int64_t columns = raster->columns;
    std::fill(out, out + columns, uint8_t{0});
    if (r < 0 || r + 1 >= raster->rows) return;
    const double* here = raster->z + r * columns;
    const double* below = here + columns;
    for (int64_t c = 0; c + 1 < columns; ++c) {
      out[c] = static_cast<uint8_t>(std::isfinite(here[c]) & std::isfinite(here[c + 1]) &
                                    std::isfinite(below[c]) & std::isfinite(below[c + 1]));
    }
  }
  int64_t BoxRows() const { return r_hi - r_lo + 1; }
};

// A corner (c, r) of a complete cell (the flags of the rows r − 1 and r): a
// vertex of the data domain.
inline bool DomainVertex(const uint8_t* above, const uint8_t* here, int64_t c, int64_t columns) {
  const bool left = c >= 1, inside = c < columns;
  return (left && (above[c - 1] | here[c - 1])) || (inside && (above[c] | here[c]));
}

// Rows' counts and ends in parallel, then the box and the numbering; false
// for no valid cell or a height beyond kMaxCoordinate.
bool Scan(const Execution& execution, Side* side);

// The domain's area as MarkComplete sums it (the complete cells' two
// triangles, row chunks of the box, the chunks' halves added in order) and
// the number of complete cells; with `complete`, every cell's flag
// (row-major, as Side::CompleteRow).
double DomainArea(const Execution& execution, const Side& side, int64_t* complete_cells,
                  std::vector<uint8_t>* complete = nullptr);

// The hull of the valid cells (grid_cells::HullAreaOfRowEnds).
double HullAreaOf(const Side& side, double cell_area);

// NodeAreas' sums for A's samples, Ω's nodes those with a finite dz.
std::vector<double> NodeAreasOf(const Execution& execution, const Side& a,
                                const std::vector<double>& dz_a);

// The offset sweep (grid_sweep.cc's, on heights): B's cell (0, 0) at A's
// cell coordinates (fc, fr), a fraction of a cell off A's lattice lines.
// Per chunk of A's box rows its sums (A's nodes, then the cells, then as
// many chunks of B's box rows' nodes); dz at A's nodes into *dz_a and at
// B's into *dz_b when not null. False for an offset on a lattice line.
bool SweepOffset(const Execution& execution, const Side& a, const Side& b,
                 const std::vector<uint8_t>& complete_a, const std::vector<uint8_t>& complete_b,
                 double fc, double fr, double cell_area, double lod,
                 std::vector<grid_cells::ChunkSums>* parts, std::vector<double>* dz_a,
                 std::vector<double>* dz_b);

}  // namespace raster_sides
}  // namespace surfreg

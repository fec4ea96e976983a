#pragma once
// The mesh of a raster's samples: the raster's own cells, each split by one
// rule (issue 26).
//
// A Delaunay triangulation of raster samples picks each cell's diagonal from
// the cell's shape. On a lattice every cell is cocircular, and after a change
// of frame (lon/lat to metres) or at UTM-sized coordinates a cell differs
// from a rectangle only by rounding, so the choice is noise, different in two
// DEMs of the same grid, which then differ between the nodes. And a node's
// hat function integrates to one cell's area only if it has six triangles.
// So raster samples are meshed in the raster's index space, by one rule:
//
//   the cell of samples (c, r), (c+1, r), (c, r+1), (c+1, r+1), all four
//   valid, is split along its diagonal from (c, r) to (c+1, r+1), into
//   (c, r) (c+1, r) (c+1, r+1) and (c, r) (c+1, r+1) (c, r+1).
//
// (Rows count down from the top, as in GDAL: on a north-up raster the
// diagonal runs from north-west to south-east.) The same grid gives the same
// surface in any CRS and after any rigid motion, and every interior node has
// six triangles. The mesh is the Delaunay triangulation of the samples with
// every grid triangle forced in by edge flips (enforce_triangles.h); the rest
// of the convex hull (nodata holes, the outline) keeps whatever triangles
// the flips leave: not data (domain.h), but walking and the overlay need a
// convex mesh.
//
// Orientation: every grid triangle is turned to the orientation most of them
// have at the given xy (exact signs), so a mirrored geotransform (rows going
// up) or a surface turned upside down is meshed like any other.
// Folds: a cell with a triangle that is then not strictly counter-clockwise
// (exact test) is folded: the grid overlaps itself there (a reprojection far
// outside its zone, a rigid tilt past a cliff) and is no height field. It
// and every cell sharing a corner with it are left out, like cells with a
// nodata corner (a folded corner lies in a neighbouring cell, so those would
// overlap it); so is a cell with a corner merged as a duplicate xy. A cell
// that still cannot be forced in (overlaps farther away) is left out too.
#include <cstdint>
#include <string>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "measure/tasks.h"

namespace surfreg {

// The triangles of the complete cells of samples with cells `cells`, six
// indices (into `cells`) per cell, by the rule above: (c, r) (c+1, r)
// (c+1, r+1), then (c, r) (c+1, r+1) (c, r+1). Cells in row-major order.
// Linear when `cells` is in row-major order (as the raster reader makes
// it), otherwise sorted first. Throws InputError naming `source` if two
// samples have the same cell. By chunks of rows on `execution`'s threads:
// the same triangles on any number.
std::vector<int32_t> GridCellTriangles(const std::vector<RasterCell>& cells, const std::string& source,
                                       const Execution& execution = Execution{});

// Renumbers the points of `triangles` (six per cell, as GridCellTriangles)
// by new_index[old] after the points were reordered or some dropped
// (new_index -1): a cell with a dropped corner is removed whole.
void RemapGridTriangles(const std::vector<int32_t>& new_index, std::vector<int32_t>* triangles);

struct GridMeshStats {
  int64_t cells = 0;          // complete cells given
  int64_t folded_cells = 0;   // of them, folded (or degenerate) at the given xy
  int64_t dropped_cells = 0;  // left out: folded, around a fold, or not enforceable
};

// Forces the cells of `cell_triangles` (six indices into `xy` per cell, as
// GridCellTriangles) into `mesh`, a valid triangulation of `xy` (normally its
// Delaunay triangulation), leaving out the folded cells and those around
// them as above. Returns, per triangle of the resulting mesh, 1 if it is
// one of the grid triangles kept (both triangles of their cell are faces).
std::vector<uint8_t> EnforceGrid(const std::vector<Point2>& xy,
                                 const std::vector<int32_t>& cell_triangles, Triangulation* mesh,
                                 GridMeshStats* stats = nullptr);

}  // namespace surfreg

#pragma once
// A surface sampled onto a raster grid: what `surfreg transform` writes
// for a .tif output (a moved DEM back on its own grid, or on another's),
// and what align can use for an aligned DEM.
//
// The surface is the piecewise-linear interpolant on its mesh, the mesh
// every command uses (measure/measures.h): the Delaunay triangulation of its
// xy, with a raster's own cells forced in when it came from one
// (measure/grid_mesh.h). A cell of the grid gets the surface's height at
// the cell's centre where that centre lies in the surface's data domain
// (measure/domain.h: not in the triangles that bridge voids, nodata holes
// or concave outlines), NaN (nodata) elsewhere. The surface and the grid
// must be in the same coordinates (no reprojection here).
#include <string>

#include "measure/surface.h"
#include "tools/io/raster_io.h"

namespace surfreg {

// `grid_template`: its size, geotransform and crs_wkt are copied (its
// values are not used). `moved` must hold at least 3 points not on a line
// (InputError otherwise, from the triangulation).
Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template);

// True if `path` ends in .tif or .tiff (any case): what WriteGeoTiff writes.
bool IsGeoTiffPath(const std::string& path);

}  // namespace surfreg

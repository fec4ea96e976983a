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
//
// A raster moved rigidly (its samples keep Surface::raster_cell) needs no
// mesh: its cells split by the rule are its mesh, so each cell triangle
// finds the grid's centres in its box by exact orientation tests (a centre
// on shared edges goes to the triangle listed first). The same heights as
// through the mesh; a raster that folds over or overlaps itself after the
// motion takes the mesh's path (which leaves those cells out).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "measure/surface.h"
#include "measure/tasks.h"
#include "io/raster_io.h"

namespace surfreg {

// `grid_template`: its size, geotransform and crs_wkt are copied (its
// values are not used). `moved` must hold at least 3 points not on a line
// (InputError otherwise, from the triangulation).
// On `execution`'s threads (the heights the same on any number).
Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template,
                        const Execution& execution = Execution{1});

// Moves points (x, y, h) in place from the grid's coordinates (h a height)
// into the surface's (e.g. lon, lat, h into a metric frame).
using GridToSurface = std::function<void(std::vector<std::array<double, 3>>*)>;

// The same for a grid in other coordinates than the surface's: each cell
// gets the height h at which the line of the cell's centre (x, y fixed, h
// varying) meets the surface, found by h ← h + (z_surface − z) over the
// mapped points (one step when the map keeps heights, as UTM does; a few
// when it tilts them, as a tangent plane does; at most 4, to 1e-9 of h).
// `to_surface` is called on the calling thread.
Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template, const GridToSurface& to_surface,
                        const Execution& execution = Execution{1});

// True if `path` ends in .tif or .tiff (any case): what WriteGeoTiff writes.
bool IsGeoTiffPath(const std::string& path);

}  // namespace surfreg

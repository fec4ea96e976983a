#pragma once
// Digital elevation models as GDAL rasters: reading one band (or a window of
// it), turning its valid cells into height samples, and writing GeoTIFFs.
// This is the only file pair that includes GDAL's raster API.
//
// Pixel convention (a half-cell error here is the classic DEM bug):
// `geotransform` is always GDAL's pixel-is-AREA form, so (column, row) =
// (0, 0) is the outer corner of the top-left cell and a cell's centre is at
// (column + 0.5, row + 0.5):
//   x = gt[0] + (column + 0.5) gt[1] + (row + 0.5) gt[2]
//   y = gt[3] + (column + 0.5) gt[4] + (row + 0.5) gt[5]
// GDAL already converts the other conventions to this one: a GeoTIFF tagged
// AREA_OR_POINT=Point (PixelIsPoint: its tie point is a cell centre) and an
// ESRI ASCII grid with xllcenter/yllcenter are shifted by half a cell when
// read (unless the GTIFF_POINT_GEO_IGNORE config option is set), so samples
// sit at cell centres whatever the file says. raster_io_test.cc checks both.
//
// Errors (unreadable file, band or window out of range, rotated or sheared
// geotransform, nothing valid) throw surfreg::InputError with one line
// starting with the file name; GDAL's own message is included when it has
// one, and GDAL prints nothing to stderr while these functions run.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/surface.h"
#include "measure/uninitialized_vector.h"

namespace surfreg {

// A block of cells; columns/rows = 0 mean "to the right/bottom edge".
struct RasterWindow {
  int column = 0, row = 0;    // top-left cell of the window
  int columns = 0, rows = 0;  // size in cells; 0 = to the edge
};

struct RasterReadOptions {
  int band = 1;         // 1-based, as in GDAL
  RasterWindow window;  // default: the whole raster
  // Threads (0: every core) reading a large window by bands of rows, each on
  // a GDAL handle of its own: the same values for any number.
  int threads = 1;
};

struct Raster {
  int columns = 0, rows = 0;
  // GDAL convention, pixel-is-area (see above); for a window, the window's
  // own (its top-left corner is the window's outer corner). Units of the CRS.
  std::array<double, 6> geotransform = {0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  std::string crs_wkt;         // WKT of the CRS; "" if the file has none
  // columns * rows, row-major, row 0 at the top; NaN = nodata. resize()
  // leaves new heights unset (their pages first touched where they are read).
  UninitializedVector<double> values;
  std::string source;          // the path (for messages)
  // Cells read as nodata because they are NaN or infinite, not because they
  // hold the band's nodata value or are masked out (ReadRaster warns).
  int64_t non_finite_cells = 0;

  // Centre of cell (column, row): the geotransform at (column + 0.5, row + 0.5).
  Point2 CellCentre(int column, int row) const;
};

// Reads one band of `path` (any raster format GDAL reads) as doubles. A cell
// is nodata, and becomes NaN, when it equals the band's nodata value, is
// masked out by the band's mask (per-dataset mask, alpha band), or is NaN or
// infinite (counted in non_finite_cells, and a warning names the file and
// the count). A file without a geotransform gets GDAL's default (0, 1, 0, 0,
// 0, 1): cell (c, r) is centred at (c + 0.5, r + 0.5).
Raster ReadRaster(const std::string& path, const RasterReadOptions& options = {});

// The valid cells as samples at cell centres, in input coordinates (CRS
// units; stored relative to an origin rounded to `origin_step`, see
// MakeSurface), in row-major order; Surface::source is raster.source and
// Surface::raster_cell holds each sample's (column, row) (the surface is
// then meshed on the raster's cells, measure/grid_mesh.h, and its data
// domain is the cells whose four corner samples are valid). If
// `cell_of_sample` is not null it receives, for sample i, the cell index
// row * columns + column. The result has passed ValidateSurface. Throws
// InputError "<source>: every cell is nodata" when no cell is valid.
// By chunks of rows on `threads`: the same samples on any number.
Surface RasterToSurface(const Raster& raster, std::vector<int64_t>* cell_of_sample,
                        double origin_step = 1.0, int threads = 1);

// The core of RasterToSurface for a window of a grid: `values` the
// window's columns × rows heights (row-major, first cell at column0, row0
// of the grid whose geotransform is given); its finite cells as samples at
// their centres, relative to *origin, or when `origin` is null to the origin
// MakeSurface would choose (`origin_step`); raster_cell in grid columns and
// rows; *cell_of_sample (if not null) each sample's index in the window. No
// check, no source; an empty surface if no cell is finite.
Surface GridCellsToSurface(const std::array<double, 6>& geotransform, int column0, int row0, int columns,
                           int rows, const double* values, const std::array<double, 3>* origin,
                           double origin_step, std::vector<int64_t>* cell_of_sample, int threads);

// Writes `raster` as a one-band Float32 GeoTIFF, DEFLATE-compressed with
// the floating-point predictor (tiled
// 256 x 256 when a side exceeds 512 cells), with its geotransform and CRS.
// NaN cells are written as a nodata value, which is set as the band's
// nodata: -9999, or when some finite value equals that (as Float32) the
// first unused one of -99999, -32768, -3.4028235e38 (float lowest), ...
// Atomic: the data go to a temporary file in the same directory, renamed to
// `path` only when complete; on any failure nothing is left behind and an
// existing `path` is unchanged. Errors are InputErrors starting with
// `label` (e.g. "flag --output"): missing directory, a finite value outside
// the Float32 range, a size mismatch, an unreadable crs_wkt, GDAL failures.
// `threads` (>= 1) compress the blocks: the file's bytes do not depend on it.
void WriteGeoTiff(const std::string& path, const Raster& raster, const std::string& label, int threads = 1);

// A one-band Float32 GeoTIFF written window by window, never held whole
// (tiled 256 x 256, DEFLATE + predictor, nodata -9999; NaN is written as nodata): into a
// temporary file next to `path`, renamed over it by Finish(). Destroyed
// unfinished (an error, an interrupt) it leaves no file. Errors throw
// InputError starting with "<label>: '<path>'".
class GeoTiffStreamWriter {
 public:
  GeoTiffStreamWriter(const std::string& path, int columns, int rows,
                      const std::array<double, 6>& geotransform, const std::string& crs_wkt,
                      const std::string& label);
  ~GeoTiffStreamWriter();
  GeoTiffStreamWriter(const GeoTiffStreamWriter&) = delete;
  GeoTiffStreamWriter& operator=(const GeoTiffStreamWriter&) = delete;

  // `values`: `count` = columns * rows, row-major, of the window at (column, row).
  void Write(int column, int row, int columns, int rows, const double* values, std::size_t count);
  void Finish();

 private:
  std::string path_, temporary_, where_;
  void* writer_ = nullptr;
  int slot_ = -1;
};

// True if the extension of `path` (case-insensitive) is one ReadSurface
// reads as a raster: .tif .tiff .vrt .asc .img .bil .hgt .dem .nc .gpkg .flt
bool IsRasterPath(const std::string& path);

}  // namespace surfreg

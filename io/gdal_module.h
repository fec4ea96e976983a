// The GDAL module, libsurfreg_gdal.so: every call into GDAL, OGR and PROJ
// (raster reading, GeoTIFF writing, CRS parsing and comparison), loaded with
// dlopen the first time a command needs it. Linked into the program, GDAL's
// ~110 shared libraries cost every process ~50 ms of dynamic loading before
// main (a whole face alignment takes 0.3-0.5 s); loaded on demand, only a
// command that reads or writes a raster or parses a CRS pays it.
//
// Internal (not installed as a header): the functions a user calls are
// raster_io.h's and geo_frame.h's. No exception crosses the module's
// boundary: each function reports failure by its return value and a
// one-line message.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/raster_io.h"

namespace surfreg {

// What the module tells of a CRS (terrain/geo_frame.h's Crs is built from it).
struct CrsFacts {
  enum Kind { kProjected, kGeographic } kind = kProjected;
  std::string name;            // GDAL's name of the CRS ("" if it has none)
  std::string wkt;             // WKT2_2019
  double metres_per_unit = 1;  // linear unit of a projected CRS
};

// Ellipsoid, prime meridian and name of a CRS's geographic CRS.
struct CrsDatum {
  double a = 0, f = 0;  // semi-major axis (m), flattening (0: a sphere)
  double prime_meridian_deg = 0;
  std::string name;
};

// The polygon rings of one layer of a vector file (a mask).
struct VectorRings {
  std::vector<std::vector<std::array<double, 2>>> rings;  // not closed explicitly
  std::vector<std::string> names;  // per ring, for messages: "feature 7 ring 2" (ring 1: exterior)
  std::string crs_wkt;             // the layer's CRS as WKT2_2019; "" if it has none
};

// How open_geotiff lays out its file.
struct GeoTiffLayout {
  float nodata = -9999.0f;
  bool tiled = true;
  int threads = 1;  // GDAL's threads compressing the blocks
};

struct GdalModule {
  // Equal to kGdalModuleVersion in both the module and its loader: a module
  // from another build is refused rather than called with other layouts.
  int version;
  // One band of `path`, nodata as NaN (raster_io.h ReadRaster). The error
  // starts with the path.
  bool (*read_raster)(const std::string& path, const RasterReadOptions& options, Raster* raster,
                      std::string* error);
  // The same without the values and the CRS: size and geotransform of the
  // window (the CRS's export loads PROJ's database: read_raster_crs, beside
  // the rows).
  bool (*read_raster_header)(const std::string& path, const RasterReadOptions& options, Raster* raster,
                             std::string* error);
  // Rows [first_row, first_row + rows) of the window into `values`
  // (columns × rows, nodata as NaN; *non_finite_cells as Raster's), on a
  // handle of the call's own: calls may run on several threads at once.
  bool (*read_raster_rows)(const std::string& path, const RasterReadOptions& options, int first_row,
                           int rows, double* values, int64_t* non_finite_cells, std::string* error);
  // The CRS of `path` as WKT ("" if it has none), as read_raster gives it.
  bool (*read_raster_crs)(const std::string& path, std::string* crs_wkt, std::string* error);
  // A CRS from user text (EPSG:n, WKT, PROJ string, "lonlat"); the error
  // follows "<label>: " and names the problem (unreadable, geocentric,
  // neither projected nor geographic, angular unit not the degree).
  bool (*parse_crs)(const std::string& text, CrsFacts* crs, std::string* error);
  // "EPSG:n" when the CRS has or matches an EPSG code, else its PROJ
  // string, else "" (also for unreadable WKT).
  std::string (*identify_crs)(const std::string& wkt);
  // The same for the UTM zone on the geographic CRS of `wkt`.
  std::string (*identify_utm)(const std::string& wkt, int zone, bool north);
  // False if the WKT is unreadable or has no ellipsoid.
  bool (*datum_of)(const std::string& wkt, CrsDatum* datum);
  // 1 if the two CRSs are the same (only their geographic CRSs compared
  // when `geographic_only`), 0 if not, -1 if one is unreadable.
  int (*same_crs)(const std::string& wkt_a, const std::string& wkt_b, bool geographic_only);
  // Latitude and longitude (WGS 84) of a point in a projected CRS.
  bool (*projected_to_lonlat)(const std::string& wkt, double x, double y, double* lat,
                              double* lon);
  // Every point (x, y = easting/longitude, northing/latitude, z) from one
  // CRS into another, in place; heights change only where the CRSs say how
  // (a vertical CRS). False, with the first point that fails, otherwise.
  bool (*transform_points)(const std::string& from_wkt, const std::string& to_wkt,
                           std::vector<std::array<double, 3>>* points, std::string* error);
  // Every ring of every Polygon and MultiPolygon feature of the layer named
  // `layer` of a vector file (the first layer when ""). The error starts
  // with the path: unreadable, no such layer (listing the layers), or no
  // polygon features (saying what the layer holds).
  bool (*read_vector_rings)(const std::string& path, const std::string& layer, VectorRings* out,
                            std::string* error);
  // A one-band Float32 GeoTIFF (no side file; DEFLATE with the
  // floating-point predictor, tiled 256 x 256 when `layout.tiled`, its blocks
  // compressed on `layout.threads` of GDAL's threads, the same bytes on any
  // number): open it (null on failure), write windows of row-major values,
  // then close it (which compresses what is left and frees the writer
  // whether or not it succeeds). Windows of doubles have NaN written as
  // `layout.nodata` (a finite value equal to it, or outside Float32, is an
  // error); windows of floats are written as they are. `where` starts the
  // errors; the caller chose `file` (a temporary name) and renames it.
  void* (*open_geotiff)(const std::string& file, int columns, int rows,
                        const std::array<double, 6>& geotransform, const std::string& crs_wkt,
                        const GeoTiffLayout& layout, const std::string& where, std::string* error);
  bool (*write_geotiff_window)(void* writer, int column, int row, int columns, int rows,
                               const double* values, std::string* error);
  bool (*write_geotiff_floats)(void* writer, int column, int row, int columns, int rows,
                               const float* values, std::string* error);
  bool (*close_geotiff)(void* writer, std::string* error);
};

constexpr int kGdalModuleVersion = 8;

// The loaded module. The first call looks for libsurfreg_gdal.so in: the
// file named by the environment variable SURFREG_GDAL_MODULE; next to the
// program (or library) holding this code; the install layout relative to
// it (../lib/surfreg/); the configured install prefix; the build tree.
// Throws InputError "<what>: needs GDAL, but ..." when none loads.
const GdalModule& Gdal(const std::string& what);

}  // namespace surfreg

// The module's one exported symbol.
extern "C" const surfreg::GdalModule* surfreg_gdal_module();

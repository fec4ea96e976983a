// Raster reading in the GDAL module (gdal_module.h): a whole band, or its
// header and then rows of it, each call on a dataset handle of its own (so
// that several threads may read one file at once: GDAL handles are not
// shared between threads).
#include <cpl_conv.h>
#include <gdal.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/gdal_module.h"
#include "io/gdal_module_internal.h"

namespace surfreg {
namespace {

// The window with sizes resolved, after checking it lies inside the raster.
RasterWindow ResolveWindow(const RasterWindow& w, int width, int height, const std::string& path) {
  RasterWindow r = w;
  if (r.columns == 0) r.columns = width - r.column;
  if (r.rows == 0) r.rows = height - r.row;
  const bool inside = w.column >= 0 && w.row >= 0 && w.columns >= 0 && w.rows >= 0 &&
                      w.column < width && w.row < height && r.columns <= width - r.column &&
                      r.rows <= height - r.row;
  if (!inside) {
    Fail(path, "window at column " + std::to_string(w.column) + ", row " + std::to_string(w.row) +
                   " of " + std::to_string(w.columns) + " x " + std::to_string(w.rows) +
                   " cells is outside the raster (" + std::to_string(width) + " x " +
                   std::to_string(height) + " cells)");
  }
  return r;
}

// An open band and its resolved window.
struct OpenBand {
  Dataset dataset;
  GDALRasterBandH band = nullptr;
  RasterWindow window;
};

// Opens `path`, checks the band and the window, and fills the raster's
// header (size, geotransform of the window, and the CRS if `with_crs`: its
// first export on a thread costs that thread a PROJ context, ~25 ms; no
// values).
OpenBand Open(const std::string& path, const RasterReadOptions& options, const QuietGdal& quiet,
              Raster* header, bool with_crs) {
  RegisterGdalOnce();
  OpenBand open;
  open.dataset.reset(GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR,
                                nullptr, nullptr, nullptr));
  if (!open.dataset) Fail(path, "cannot open as a raster" + quiet.Detail());
  GDALDatasetH ds = open.dataset.get();
  const int bands = GDALGetRasterCount(ds);
  if (options.band < 1 || options.band > bands) {
    Fail(path, "band " + std::to_string(options.band) + " of " + std::to_string(bands));
  }
  const RasterWindow w = ResolveWindow(options.window, GDALGetRasterXSize(ds), GDALGetRasterYSize(ds), path);
  open.window = w;
  open.band = GDALGetRasterBand(ds, options.band);

  Raster& raster = *header;
  raster.source = path;
  raster.columns = w.columns;
  raster.rows = w.rows;
  double gt[6] = {0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  if (GDALGetGeoTransform(ds, gt) != CE_None) {
    gt[0] = 0.0, gt[1] = 1.0, gt[2] = 0.0, gt[3] = 0.0, gt[4] = 0.0, gt[5] = 1.0;
  }
  if (gt[2] != 0.0 || gt[4] != 0.0) {
    Fail(path, "rotated or sheared geotransform (row/column terms " + Number(gt[2]) + ", " +
                   Number(gt[4]) + ") is not supported; warp it to a north-up grid first");
  }
  if (!(gt[1] != 0.0 && gt[5] != 0.0 && std::isfinite(gt[1]) && std::isfinite(gt[5]))) {
    Fail(path, "cell size " + Number(gt[1]) + " x " + Number(gt[5]) + " is not usable");
  }
  // The window's outer corner becomes the origin of its own geotransform.
  gt[0] += w.column * gt[1];
  gt[3] += w.row * gt[5];
  for (int k = 0; k < 6; ++k) raster.geotransform[k] = gt[k];
  if (with_crs) {
    const char* wkt = GDALGetProjectionRef(ds);
    raster.crs_wkt = wkt == nullptr ? "" : wkt;
  }
  return open;
}

// Rows [first, first + rows) of the window into `values` (columns × rows),
// as doubles with NaN for nodata: the band's nodata value, infinities and
// NaN (counted in *non_finite), and what the band's mask excludes when it
// says more than the nodata value does (per-dataset mask, alpha band).
void ReadRows(const OpenBand& open, const std::string& path, int band_number, int first, int rows,
              double* values, int64_t* non_finite, const QuietGdal& quiet) {
  const RasterWindow& w = open.window;
  GDALRasterBandH band = open.band;
  const std::size_t count = static_cast<std::size_t>(w.columns) * static_cast<std::size_t>(rows);
  if (GDALRasterIO(band, GF_Read, w.column, w.row + first, w.columns, rows, values, w.columns, rows,
                   GDT_Float64, 0, 0) != CE_None) {
    Fail(path, "cannot read band " + std::to_string(band_number) + quiet.Detail());
  }
  int has_nodata = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  // A Float32 band holds the nodata value rounded to float, which differs
  // from the double GDAL reports when that is not representable (-9999.1).
  double nodata_as_stored = nodata;
  if (GDALGetRasterDataType(band) == GDT_Float32 && std::fabs(nodata) <= 3.4028234663852886e38) {
    nodata_as_stored = static_cast<float>(nodata);
  }
  int64_t bad = 0;
  for (std::size_t i = 0; i < count; ++i) {
    double& v = values[i];
    const bool is_nodata = has_nodata != 0 && (v == nodata || v == nodata_as_stored);
    if (!is_nodata && !std::isfinite(v)) ++bad;
    if (is_nodata || !std::isfinite(v)) v = std::numeric_limits<double>::quiet_NaN();
  }
  *non_finite = bad;
  const int flags = GDALGetMaskFlags(band);
  if ((flags & GMF_ALL_VALID) != 0 || (flags & GMF_NODATA) != 0) return;
  GDALRasterBandH mask = GDALGetMaskBand(band);
  if (mask == nullptr) return;
  std::vector<unsigned char> valid(count);
  if (GDALRasterIO(mask, GF_Read, w.column, w.row + first, w.columns, rows, valid.data(), w.columns, rows,
                   GDT_Byte, 0, 0) != CE_None) {
    Fail(path, "cannot read the mask of the band" + quiet.Detail());
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (valid[i] == 0) values[i] = std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace

bool ReadRasterEntry(const std::string& path, const RasterReadOptions& options, Raster* raster,
                     std::string* error) {
  return Guarded(error, path, [&] {
    QuietGdal quiet;
    Raster out;
    const OpenBand open = Open(path, options, quiet, &out, true);
    out.values.resize(static_cast<std::size_t>(out.columns) * static_cast<std::size_t>(out.rows));
    ReadRows(open, path, options.band, 0, out.rows, out.values.data(), &out.non_finite_cells, quiet);
    *raster = std::move(out);
  });
}

bool ReadRasterHeaderEntry(const std::string& path, const RasterReadOptions& options, Raster* raster,
                           std::string* error) {
  return Guarded(error, path, [&] {
    QuietGdal quiet;
    Raster out;
    Open(path, options, quiet, &out, false);
    *raster = std::move(out);
  });
}

bool ReadRasterRowsEntry(const std::string& path, const RasterReadOptions& options, int first_row,
                         int rows, double* values, int64_t* non_finite_cells, std::string* error) {
  return Guarded(error, path, [&] {
    QuietGdal quiet;
    Raster header;
    const OpenBand open = Open(path, options, quiet, &header, false);
    if (first_row < 0 || rows < 0 || first_row > header.rows - rows) {
      Fail(path, "rows " + std::to_string(first_row) + " to " + std::to_string(first_row + rows) +
                     " are outside the window of " + std::to_string(header.rows) + " rows");
    }
    ReadRows(open, path, options.band, first_row, rows, values, non_finite_cells, quiet);
  });
}

bool ReadRasterCrsEntry(const std::string& path, std::string* crs_wkt, std::string* error) {
  return Guarded(error, path, [&] {
    QuietGdal quiet;
    RegisterGdalOnce();
    const Dataset dataset(GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR,
                                     nullptr, nullptr, nullptr));
    if (!dataset) Fail(path, "cannot open as a raster" + quiet.Detail());
    const char* wkt = GDALGetProjectionRef(dataset.get());
    *crs_wkt = wkt == nullptr ? "" : wkt;
  });
}

}  // namespace surfreg

// GDAL raster reading and GeoTIFF writing (see raster_io.h). GDAL's C API is
// used so that every handle has one obvious owner (a unique_ptr below).
#include "tools/io/raster_io.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>

#include "measure/input_error.h"
#include "tools/atomic_file.h"
#include "tools/interrupt.h"
#include "tools/io/surface_reader_internal.h"

namespace surfreg {
namespace {

void RegisterGdalOnce() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// While alive, GDAL errors and warnings on this thread go here instead of
// stderr (GDAL's handler stack is per thread); the last failure's text is
// kept for our own one-line message.
class QuietGdal {
 public:
  QuietGdal() { CPLPushErrorHandlerEx(&Handler, this); }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;

  bool failed() const { return failed_; }
  // " (GDAL: <last failure>)", or "" when GDAL reported none.
  std::string Detail() const { return last_.empty() ? "" : " (GDAL: " + last_ + ")"; }

 private:
  static void CPL_STDCALL Handler(CPLErr level, CPLErrorNum, const char* message) {
    auto* self = static_cast<QuietGdal*>(CPLGetErrorHandlerUserData());
    if (self == nullptr || level < CE_Failure) return;
    self->failed_ = true;
    self->last_ = message == nullptr ? "" : message;
    for (char& c : self->last_) {
      if (c == '\n' || c == '\r') c = ' ';  // our messages are one line
    }
  }

  bool failed_ = false;
  std::string last_;
};

struct DatasetCloser {
  void operator()(void* dataset) const { GDALClose(static_cast<GDALDatasetH>(dataset)); }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

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

// Sets to NaN every cell that the band's mask marks invalid, when the mask
// says more than the nodata value does (per-dataset mask, alpha band).
void ApplyMask(GDALRasterBandH band, const RasterWindow& w, Raster* raster,
               const QuietGdal& quiet) {
  const int flags = GDALGetMaskFlags(band);
  if ((flags & GMF_ALL_VALID) != 0 || (flags & GMF_NODATA) != 0) return;
  GDALRasterBandH mask = GDALGetMaskBand(band);
  if (mask == nullptr) return;
  std::vector<unsigned char> valid(raster->values.size());
  if (GDALRasterIO(mask, GF_Read, w.column, w.row, w.columns, w.rows, valid.data(), w.columns,
                   w.rows, GDT_Byte, 0, 0) != CE_None) {
    Fail(raster->source, "cannot read the mask of the band" + quiet.Detail());
  }
  for (std::size_t i = 0; i < valid.size(); ++i) {
    if (valid[i] == 0) raster->values[i] = std::numeric_limits<double>::quiet_NaN();
  }
}

// NaN for the nodata value, infinities, and what the band's mask excludes.
void MarkNodata(GDALRasterBandH band, const RasterWindow& w, Raster* raster,
                const QuietGdal& quiet) {
  int has_nodata = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  // A Float32 band holds the nodata value rounded to float, which differs
  // from the double GDAL reports when that is not representable (-9999.1).
  double nodata_as_stored = nodata;
  if (GDALGetRasterDataType(band) == GDT_Float32 && std::fabs(nodata) <= 3.4028234663852886e38) {
    nodata_as_stored = static_cast<float>(nodata);
  }
  for (double& v : raster->values) {
    const bool is_nodata = has_nodata != 0 && (v == nodata || v == nodata_as_stored);
    if (is_nodata || !std::isfinite(v)) v = std::numeric_limits<double>::quiet_NaN();
  }
  ApplyMask(band, w, raster, quiet);
}

}  // namespace

Point2 Raster::CellCentre(int column, int row) const {
  const double c = column + 0.5, r = row + 0.5;
  const auto& gt = geotransform;
  return {gt[0] + c * gt[1] + r * gt[2], gt[3] + c * gt[4] + r * gt[5]};
}

Raster ReadRaster(const std::string& path, const RasterReadOptions& options) {
  RegisterGdalOnce();
  QuietGdal quiet;
  Dataset dataset(GDALOpenEx(path.c_str(),
                             GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, nullptr,
                             nullptr, nullptr));
  if (!dataset) Fail(path, "cannot open as a raster" + quiet.Detail());
  GDALDatasetH ds = dataset.get();
  const int bands = GDALGetRasterCount(ds);
  if (options.band < 1 || options.band > bands) {
    Fail(path, "band " + std::to_string(options.band) + " of " + std::to_string(bands));
  }
  const RasterWindow w =
      ResolveWindow(options.window, GDALGetRasterXSize(ds), GDALGetRasterYSize(ds), path);

  Raster raster;
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
  const char* wkt = GDALGetProjectionRef(ds);
  raster.crs_wkt = wkt == nullptr ? "" : wkt;

  GDALRasterBandH band = GDALGetRasterBand(ds, options.band);
  raster.values.resize(static_cast<std::size_t>(w.columns) * static_cast<std::size_t>(w.rows));
  if (GDALRasterIO(band, GF_Read, w.column, w.row, w.columns, w.rows, raster.values.data(),
                   w.columns, w.rows, GDT_Float64, 0, 0) != CE_None) {
    Fail(path, "cannot read band " + std::to_string(options.band) + quiet.Detail());
  }
  MarkNodata(band, w, &raster, quiet);
  return raster;
}

Surface RasterToSurface(const Raster& raster, std::vector<int64_t>* cell_of_sample,
                        double origin_step) {
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  if (cell_of_sample != nullptr) cell_of_sample->clear();
  for (int row = 0; row < raster.rows; ++row) {
    for (int column = 0; column < raster.columns; ++column) {
      const int64_t cell = static_cast<int64_t>(row) * raster.columns + column;
      const double z = raster.values[static_cast<std::size_t>(cell)];
      if (!std::isfinite(z)) continue;
      const Point2 centre = raster.CellCentre(column, row);
      points.push_back({centre.x, centre.y, z});
      cells.push_back({column, row});
      if (cell_of_sample != nullptr) cell_of_sample->push_back(cell);
    }
  }
  if (points.empty()) Fail(raster.source, "every cell is nodata");
  Surface surface = MakeSurface(points, {}, raster.source, origin_step);
  surface.raster_cell = std::move(cells);  // meshed on its own cells (measure/grid_mesh.h)
  ValidateSurface(surface);
  return surface;
}

namespace {

// True if some finite value, rounded to Float32, equals `candidate`.
bool IsUsed(const std::vector<double>& values, float candidate) {
  constexpr double kMax = std::numeric_limits<float>::max();
  for (double v : values) {
    if (std::isfinite(v) && std::fabs(v) <= kMax && static_cast<float>(v) == candidate) return true;
  }
  return false;
}

float ChooseNodata(const std::vector<double>& values) {
  const float preferred[] = {-9999.0f, -99999.0f, -32768.0f, std::numeric_limits<float>::lowest()};
  for (float candidate : preferred) {
    if (!IsUsed(values, candidate)) return candidate;
  }
  // Every usual value is data: step down from -9999 (at most size + 1 tries).
  for (float candidate = -10000.0f;; candidate -= 1.0f) {
    if (!IsUsed(values, candidate)) return candidate;
  }
}

// Sets a GDAL configuration option on this thread for the object's lifetime.
class ScopedConfigOption {
 public:
  ScopedConfigOption(const char* key, const char* value) : key_(key) {
    const char* old = CPLGetThreadLocalConfigOption(key, nullptr);
    had_old_ = old != nullptr;
    if (had_old_) old_ = old;
    CPLSetThreadLocalConfigOption(key, value);
  }
  ~ScopedConfigOption() { CPLSetThreadLocalConfigOption(key_, had_old_ ? old_.c_str() : nullptr); }
  ScopedConfigOption(const ScopedConfigOption&) = delete;
  ScopedConfigOption& operator=(const ScopedConfigOption&) = delete;

 private:
  const char* key_;
  bool had_old_ = false;
  std::string old_;
};

std::string TemporaryName(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
}

// Creates and fills the GeoTIFF at `temporary` (closed on return).
void WriteGeoTiffFile(const std::string& temporary, const Raster& raster,
                      const std::string& where) {
  QuietGdal quiet;
  GDALDriverH driver = GDALGetDriverByName("GTiff");
  if (driver == nullptr) Fail(where, "GDAL has no GTiff driver");
  const bool tiled = raster.columns > 512 || raster.rows > 512;
  const char* options[] = {"COMPRESS=DEFLATE", "BIGTIFF=IF_SAFER", tiled ? "TILED=YES" : nullptr,
                           "BLOCKXSIZE=256",   "BLOCKYSIZE=256",   nullptr};
  Dataset dataset(GDALCreate(driver, temporary.c_str(), raster.columns, raster.rows, 1, GDT_Float32,
                             const_cast<char**>(options)));
  if (!dataset) Fail(where, "cannot create" + quiet.Detail());
  GDALDatasetH ds = dataset.get();
  double gt[6];
  for (int k = 0; k < 6; ++k) gt[k] = raster.geotransform[k];
  if (GDALSetGeoTransform(ds, gt) != CE_None)
    Fail(where, "cannot set the geotransform" + quiet.Detail());
  if (!raster.crs_wkt.empty() && GDALSetProjection(ds, raster.crs_wkt.c_str()) != CE_None) {
    Fail(where, "unreadable CRS" + quiet.Detail());
  }
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  const float nodata = ChooseNodata(raster.values);
  if (GDALSetRasterNoDataValue(band, nodata) != CE_None) {
    Fail(where, "cannot set the nodata value" + quiet.Detail());
  }
  constexpr double kMax = std::numeric_limits<float>::max();
  std::vector<float> line(static_cast<std::size_t>(raster.columns));
  for (int row = 0; row < raster.rows; ++row) {
    const double* in = raster.values.data() + static_cast<std::size_t>(row) * raster.columns;
    for (int column = 0; column < raster.columns; ++column) {
      const double v = in[column];
      if (std::isfinite(v) && std::fabs(v) > kMax) {
        Fail(where, "value " + Number(v) + " at column " + std::to_string(column) + ", row " +
                        std::to_string(row) + " does not fit Float32");
      }
      line[static_cast<std::size_t>(column)] = std::isfinite(v) ? static_cast<float>(v) : nodata;
    }
    if (GDALRasterIO(band, GF_Write, 0, row, raster.columns, 1, line.data(), raster.columns, 1,
                     GDT_Float32, 0, 0) != CE_None) {
      Fail(where, "cannot write" + quiet.Detail());
    }
  }
  dataset.reset();  // flushes and compresses the last blocks
  if (quiet.failed()) Fail(where, "cannot write" + quiet.Detail());
}

}  // namespace

void WriteGeoTiff(const std::string& path, const Raster& raster, const std::string& label) {
  const std::string where = label + ": '" + path + "'";
  const std::size_t cells =
      static_cast<std::size_t>(std::max(raster.columns, 0)) * std::max(raster.rows, 0);
  if (raster.columns <= 0 || raster.rows <= 0 || raster.values.size() != cells) {
    Fail(where, "raster of " + std::to_string(raster.columns) + " x " +
                    std::to_string(raster.rows) + " cells has " +
                    std::to_string(raster.values.size()) + " values");
  }
  CheckOutputPath(path, label);
  RegisterGdalOnce();
  const std::string temporary = TemporaryName(path);
  // No .aux.xml side file: what GeoTIFF tags cannot hold is not kept.
  const ScopedConfigOption no_side_file("GDAL_PAM_ENABLED", "NO");
  const int slot = RegisterTemporary(temporary);  // an interrupted run removes it
  try {
    WriteGeoTiffFile(temporary, raster, where);
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
      Fail(where, std::string("cannot rename the temporary file: ") + std::strerror(errno));
    }
  } catch (...) {
    std::remove(temporary.c_str());
    UnregisterTemporary(slot);
    throw;
  }
  UnregisterTemporary(slot);
}

bool IsRasterPath(const std::string& path) {
  static const char* const kExtensions[] = {".tif", ".tiff", ".vrt", ".asc",  ".img", ".bil",
                                            ".hgt", ".dem",  ".nc",  ".gpkg", ".flt"};
  const std::string ext = io_internal::Extension(path);
  for (const char* known : kExtensions) {
    if (ext == known) return true;
  }
  return false;
}

}  // namespace surfreg

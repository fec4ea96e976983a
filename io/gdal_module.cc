// libsurfreg_gdal.so: the only code that calls GDAL, OGR and PROJ (see
// gdal_module.h). GDAL's C API for rasters, so that every handle has one
// obvious owner (a unique_ptr below); OGRSpatialReference for CRSs.
#include "io/gdal_module.h"
#include "io/gdal_module_internal.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace surfreg {

// Vector masks: gdal_module_vector.cc.
bool ReadVectorRings(const std::string& path, const std::string& layer, VectorRings* out,
                     std::string* error);
// Rasters: gdal_module_raster.cc.
bool ReadRasterEntry(const std::string& path, const RasterReadOptions& options, Raster* raster,
                     std::string* error);
bool ReadRasterHeaderEntry(const std::string& path, const RasterReadOptions& options, Raster* raster,
                           std::string* error);
bool ReadRasterRowsEntry(const std::string& path, const RasterReadOptions& options, int first_row,
                         int rows, double* values, int64_t* non_finite_cells, std::string* error);
bool ReadRasterCrsEntry(const std::string& path, std::string* crs_wkt, std::string* error);

namespace {

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

// --- CRSs ---------------------------------------------------------------

// At most 60 characters of user text, for messages.
std::string Shown(const std::string& text) {
  std::string one_line = text.size() > 60 ? text.substr(0, 57) + "..." : text;
  for (char& c : one_line) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return "'" + one_line + "'";
}

std::string Trim(const std::string& text) {
  std::size_t b = 0, e = text.size();
  while (b < e && std::isspace(static_cast<unsigned char>(text[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
  return text.substr(b, e - b);
}

// "EPSG:nnnn" when the CRS has an EPSG code, or is one of the EPSG
// catalogue but for its names or axis order (an ESRI .prj's "GCS_WGS_1984",
// our longitude-first WGS 84), else its PROJ string, else "".
std::string Identify(const OGRSpatialReference& srs) {
  QuietGdal quiet;
  const auto code_of = [](const OGRSpatialReference& s) {
    const char* authority = s.GetAuthorityName(nullptr);
    const char* code = s.GetAuthorityCode(nullptr);
    return authority != nullptr && code != nullptr ? std::string(authority) + ":" + code
                                                   : std::string();
  };
  std::string id = code_of(srs);
  if (!id.empty()) return id;
  int n = 0;
  int* confidence = nullptr;
  OGRSpatialReferenceH* matches = srs.FindMatches(nullptr, &n, &confidence);
  const char* const same[] = {"CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS",
                              "IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", nullptr};
  for (int i = 0; i < n && id.empty(); ++i) {
    const OGRSpatialReference* match = OGRSpatialReference::FromHandle(matches[i]);
    const char* authority = match->GetAuthorityName(nullptr);
    if (authority != nullptr && std::string(authority) == "EPSG" && srs.IsSame(match, same)) {
      id = code_of(*match);
    }
  }
  if (matches != nullptr) OSRFreeSRSArray(matches);
  CPLFree(confidence);
  if (!id.empty()) return id;
  char* proj = nullptr;
  if (srs.exportToProj4(&proj) == OGRERR_NONE && proj != nullptr) id = Trim(proj);
  CPLFree(proj);
  return id;
}

// The CRS of `wkt` with x = easting/longitude, y = northing/latitude; null
// if unreadable.
std::unique_ptr<OGRSpatialReference> Import(const std::string& wkt) {
  auto srs = std::make_unique<OGRSpatialReference>();
  srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  QuietGdal quiet;
  if (wkt.empty() || srs->importFromWkt(wkt.c_str()) != OGRERR_NONE) return nullptr;
  return srs;
}

bool ParseCrs(const std::string& text, CrsFacts* crs, std::string* error) {
  OGRSpatialReference srs;
  QuietGdal quiet;
  // Config text must not make us read files or the network.
  const char* const options[] = {"ALLOW_NETWORK_ACCESS=NO", "ALLOW_FILE_ACCESS=NO", nullptr};
  if (srs.SetFromUserInput(text.c_str(), options) != OGRERR_NONE) {
    *error = "unreadable CRS " + Shown(text) + quiet.Plain();
    return false;
  }
  const char* name = srs.GetName();
  crs->name = name != nullptr && *name != '\0' ? name : Shown(text);
  const std::string what = "CRS '" + crs->name + "'";
  if (srs.IsGeocentric()) {
    *error = what + " is geocentric; a height field needs a geographic or projected CRS";
    return false;
  }
  if (srs.IsGeographic()) {
    const double degree = std::acos(-1.0) / 180.0;
    if (std::fabs(srs.GetAngularUnits() - degree) > 1e-12 * degree) {
      *error = what + ": angular unit is not the degree";
      return false;
    }
    crs->kind = CrsFacts::kGeographic;
  } else if (srs.IsProjected() || srs.IsLocal()) {
    crs->kind = CrsFacts::kProjected;
    crs->metres_per_unit = srs.GetLinearUnits();
  } else {
    *error = what + " is neither projected nor geographic";
    return false;
  }
  char* wkt = nullptr;
  const char* const wkt_options[] = {"FORMAT=WKT2_2019", nullptr};
  if (srs.exportToWkt(&wkt, wkt_options) != OGRERR_NONE || wkt == nullptr) {
    CPLFree(wkt);
    *error = what + ": cannot be written as WKT" + quiet.Plain();
    return false;
  }
  crs->wkt = wkt;
  CPLFree(wkt);
  return true;
}

std::string IdentifyCrs(const std::string& wkt) {
  const auto srs = Import(wkt);
  return srs ? Identify(*srs) : "";
}

std::string IdentifyUtm(const std::string& wkt, int zone, bool north) {
  const auto geographic = Import(wkt);
  if (!geographic) return "";
  OGRSpatialReference utm;
  QuietGdal quiet;
  if (utm.CopyGeogCSFrom(geographic.get()) != OGRERR_NONE ||
      utm.SetUTM(zone, north ? TRUE : FALSE) != OGRERR_NONE) {
    return "";
  }
  return Identify(utm);
}

bool DatumOf(const std::string& wkt, CrsDatum* datum) {
  const auto srs = Import(wkt);
  if (!srs) return false;
  OGRErr error = OGRERR_NONE;
  const double a = srs->GetSemiMajor(&error);
  if (error != OGRERR_NONE || !(a > 0)) return false;
  const double inverse_f = srs->GetInvFlattening(&error);
  datum->a = a;
  datum->f = inverse_f > 0 ? 1.0 / inverse_f : 0.0;  // 0 = sphere
  datum->prime_meridian_deg = srs->GetPrimeMeridian();
  const char* name = srs->GetAttrValue("GEOGCS");
  datum->name = name != nullptr ? name : "";
  return true;
}

int SameCrs(const std::string& wkt_a, const std::string& wkt_b, bool geographic_only) {
  const auto a = Import(wkt_a), b = Import(wkt_b);
  if (!a || !b) return -1;
  return (geographic_only ? a->IsSameGeogCS(b.get()) : a->IsSame(b.get())) ? 1 : 0;
}

bool ProjectedToLonLat(const std::string& wkt, double x, double y, double* lat, double* lon) {
  QuietGdal quiet;
  const auto source = Import(wkt);
  if (!source) return false;
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> transform(
      OGRCreateCoordinateTransformation(source.get(), &wgs84));
  if (!transform) return false;
  double px = x, py = y;
  if (!transform->Transform(1, &px, &py)) return false;
  *lon = px, *lat = py;
  return true;
}

bool TransformPoints(const std::string& from_wkt, const std::string& to_wkt,
                     std::vector<std::array<double, 3>>* points, std::string* error) {
  QuietGdal quiet;
  const auto from = Import(from_wkt), to = Import(to_wkt);
  if (!from || !to) {
    *error = "unreadable CRS" + quiet.Plain();
    return false;
  }
  std::unique_ptr<OGRCoordinateTransformation> transform(
      OGRCreateCoordinateTransformation(from.get(), to.get()));
  if (!transform) {
    *error = "no transformation between the two CRSs" + quiet.Plain();
    return false;
  }
  const std::size_t n = points->size();
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = (*points)[i][0], y[i] = (*points)[i][1], z[i] = (*points)[i][2];
  std::vector<int> ok(n, 0);
  // In blocks: PROJ's per-call overhead is large for one point, and an int
  // count caps a call anyway.
  constexpr std::size_t kBlock = 1 << 16;
  for (std::size_t b = 0; b < n; b += kBlock) {
    const int count = static_cast<int>(std::min(kBlock, n - b));
    transform->Transform(count, &x[b], &y[b], &z[b], ok.data() + b);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) {
      char what[160];
      std::snprintf(what, sizeof(what), "point %zu (%.9g, %.9g) cannot be transformed", i + 1,
                    (*points)[i][0], (*points)[i][1]);
      *error = what + quiet.Plain();
      return false;
    }
    (*points)[i] = {x[i], y[i], z[i]};
  }
  return true;
}

// --- the entry points ---------------------------------------------------

// A GeoTIFF being written window by window (GdalModule::open_geotiff).
struct GeoTiffStream {
  Dataset dataset;
  GDALRasterBandH band = nullptr;
  std::string where;
  float nodata = 0.0f;
  std::vector<float> buffer;
};

void* OpenGeoTiffEntry(const std::string& file, int columns, int rows,
                       const std::array<double, 6>& geotransform, const std::string& crs_wkt,
                       const GeoTiffLayout& layout, const std::string& where, std::string* error) {
  auto stream = std::make_unique<GeoTiffStream>();
  stream->where = where;
  stream->nodata = layout.nodata;
  const bool ok = Guarded(error, where, [&] {
    RegisterGdalOnce();
    const ScopedConfigOption no_side_file("GDAL_PAM_ENABLED", "NO");
    QuietGdal quiet;
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    if (driver == nullptr) Fail(where, "GDAL has no GTiff driver");
    // GDAL's worker threads compress the blocks (the same bytes as one
    // thread). The floating-point predictor and the fastest level: a smaller
    // file than level 6 without it, in about half the compression time.
    const std::string num_threads = "NUM_THREADS=" + std::to_string(std::max(layout.threads, 1));
    const char* options[] = {"COMPRESS=DEFLATE",  "PREDICTOR=3",    "ZLEVEL=1",
                             "BIGTIFF=IF_SAFER",  num_threads.c_str(),
                             layout.tiled ? "TILED=YES" : nullptr, "BLOCKXSIZE=256", "BLOCKYSIZE=256", nullptr};
    stream->dataset.reset(GDALCreate(driver, file.c_str(), columns, rows, 1, GDT_Float32,
                                     const_cast<char**>(options)));
    if (!stream->dataset) Fail(where, "cannot create" + quiet.Detail());
    GDALDatasetH ds = stream->dataset.get();
    double gt[6];
    for (int k = 0; k < 6; ++k) gt[k] = geotransform[k];
    if (GDALSetGeoTransform(ds, gt) != CE_None) Fail(where, "cannot set the geotransform" + quiet.Detail());
    if (!crs_wkt.empty() && GDALSetProjection(ds, crs_wkt.c_str()) != CE_None) {
      Fail(where, "unreadable CRS" + quiet.Detail());
    }
    stream->band = GDALGetRasterBand(ds, 1);
    if (GDALSetRasterNoDataValue(stream->band, layout.nodata) != CE_None) {
      Fail(where, "cannot set the nodata value" + quiet.Detail());
    }
  });
  return ok ? stream.release() : nullptr;
}

bool WriteGeoTiffWindowEntry(void* writer, int column, int row, int columns, int rows,
                             const double* values, std::string* error) {
  auto* stream = static_cast<GeoTiffStream*>(writer);
  return Guarded(error, stream->where, [&] {
    QuietGdal quiet;
    constexpr double kMax = std::numeric_limits<float>::max();
    stream->buffer.resize(static_cast<std::size_t>(columns) * rows);
    for (std::size_t i = 0; i < stream->buffer.size(); ++i) {
      const double v = values[i];
      if (std::isfinite(v) && (std::fabs(v) > kMax || static_cast<float>(v) == stream->nodata)) {
        Fail(stream->where, "value " + Number(v) + " near column " + std::to_string(column) +
                                ", row " + std::to_string(row) +
                                (std::fabs(v) > kMax ? " does not fit Float32" : " is the nodata value"));
      }
      stream->buffer[i] = std::isfinite(v) ? static_cast<float>(v) : stream->nodata;
    }
    if (GDALRasterIO(stream->band, GF_Write, column, row, columns, rows, stream->buffer.data(),
                     columns, rows, GDT_Float32, 0, 0) != CE_None) {
      Fail(stream->where, "cannot write" + quiet.Detail());
    }
  });
}

bool WriteGeoTiffFloatsEntry(void* writer, int column, int row, int columns, int rows, const float* values,
                             std::string* error) {
  auto* stream = static_cast<GeoTiffStream*>(writer);
  return Guarded(error, stream->where, [&] {
    QuietGdal quiet;
    if (GDALRasterIO(stream->band, GF_Write, column, row, columns, rows, const_cast<float*>(values), columns,
                     rows, GDT_Float32, 0, 0) != CE_None) {
      Fail(stream->where, "cannot write" + quiet.Detail());
    }
  });
}

bool CloseGeoTiffEntry(void* writer, std::string* error) {
  std::unique_ptr<GeoTiffStream> stream(static_cast<GeoTiffStream*>(writer));
  return Guarded(error, stream->where, [&] {
    // As when opened: the file holds every tag, no .aux.xml beside it.
    const ScopedConfigOption no_side_file("GDAL_PAM_ENABLED", "NO");
    QuietGdal quiet;
    stream->dataset.reset();  // flushes and compresses the last blocks
    if (quiet.failed()) Fail(stream->where, "cannot write" + quiet.Detail());
  });
}

const GdalModule kModule = {kGdalModuleVersion,    &ReadRasterEntry,    &ReadRasterHeaderEntry,
                            &ReadRasterRowsEntry,  &ReadRasterCrsEntry,   &ParseCrs,
                            &IdentifyCrs,          &IdentifyUtm,        &DatumOf,
                            &SameCrs,              &ProjectedToLonLat,  &TransformPoints,
                            &ReadVectorRings,      &OpenGeoTiffEntry,   &WriteGeoTiffWindowEntry, &WriteGeoTiffFloatsEntry,
                            &CloseGeoTiffEntry};

}  // namespace
}  // namespace surfreg

extern "C" __attribute__((visibility("default"))) const surfreg::GdalModule* surfreg_gdal_module() {
  return &surfreg::kModule;
}

#pragma once
// The raster I/O tests' fixture (a temporary directory) and helpers:
// fixture files written through GDAL's own API, independent of the code
// under test; an error's one-line message; CRS comparison.
#include <cpl_conv.h>
#include <dirent.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <functional>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/raster_io.h"
#include "measure/input_error.h"
#include "tests/testing/file_checks.h"

namespace surfreg {

inline const double kNaN = std::nan("");

class RasterIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    GDALAllRegister();
    std::string pattern = ::testing::TempDir() + "raster_io_test_XXXXXX";
    ASSERT_NE(mkdtemp(&pattern[0]), nullptr);
    dir_ = pattern + "/";
  }
  void TearDown() override {
    for (const std::string& name : Entries()) std::remove((dir_ + name).c_str());
    ::rmdir(dir_.c_str());
  }
  std::string Path(const std::string& name) const { return dir_ + name; }
  std::set<std::string> Entries() const {
    std::set<std::string> names;
    if (DIR* d = ::opendir(dir_.c_str())) {
      while (dirent* e = ::readdir(d)) {
        const std::string n = e->d_name;
        if (n != "." && n != "..") names.insert(n);
      }
      ::closedir(d);
    }
    return names;
  }
  std::string WriteText(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
    return Path(name);
  }
  std::string dir_;
};

// One-line InputError messages, with nothing on stderr (file_checks.h).
inline std::string ErrorOf(const std::function<void()>& f) { return testing::SilentErrorOf(f); }
using testing::Contains;

inline std::string Wkt(const char* user_input) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  EXPECT_EQ(OSRSetFromUserInput(srs, user_input), OGRERR_NONE);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  std::string out = wkt;
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  return out;
}

inline bool SameCrs(const std::string& a, const std::string& b) {
  OGRSpatialReferenceH sa = OSRNewSpatialReference(a.c_str());
  OGRSpatialReferenceH sb = OSRNewSpatialReference(b.c_str());
  const bool same = sa != nullptr && sb != nullptr && OSRIsSame(sa, sb);
  OSRDestroySpatialReference(sa);
  OSRDestroySpatialReference(sb);
  return same;
}

// A GeoTIFF written with GDAL directly: `bands` Float64 bands, band b's cell
// i = 100 b + i; `setup` may change the dataset before it is closed.
inline std::string MakeTiff(const std::string& path, int columns, int rows, int bands, const double gt[6],
                     const std::function<void(GDALDatasetH)>& setup = nullptr) {
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), columns, rows, bands,
                               GDT_Float64, nullptr);
  EXPECT_NE(ds, nullptr);
  GDALSetGeoTransform(ds, const_cast<double*>(gt));
  for (int b = 1; b <= bands; ++b) {
    std::vector<double> v(static_cast<size_t>(columns) * rows);
    for (size_t i = 0; i < v.size(); ++i) v[i] = 100.0 * b + static_cast<double>(i);
    EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(ds, b), GF_Write, 0, 0, columns, rows, v.data(),
                           columns, rows, GDT_Float64, 0, 0),
              CE_None);
  }
  if (setup) setup(ds);
  GDALClose(ds);
  return path;
}

inline Raster SampleRaster() {
  Raster r;
  r.columns = 5, r.rows = 4;
  r.geotransform = {1000.0, 2.0, 0.0, 5000.0, 0.0, -2.0};
  r.crs_wkt = Wkt("EPSG:32760");
  for (int i = 0; i < 20; ++i) r.values.push_back(0.25 * i - 1.5);
  r.values[3] = kNaN, r.values[7] = kNaN, r.values[19] = kNaN;
  return r;
}

}  // namespace surfreg

// GDAL rasters: GeoTIFF round trip, nodata/mask/NaN handling, bands,
// windows, the pixel-is-area/point convention (against hand-computed cell
// centres), atomic writes and every error. Fixture files are written by the
// tests, as text (.asc) or through GDAL's own API (independent of the code
// under test).
#include "io/raster_io.h"

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

#include "measure/input_error.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

const double kNaN = std::nan("");

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

// The InputError message of `f` ("" if it does not throw); checks that it is
// one line and that GDAL printed nothing to stderr.
std::string ErrorOf(const std::function<void()>& f) {
  ::testing::internal::CaptureStderr();
  std::string message;
  try {
    f();
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  return message;
}

::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

std::string Wkt(const char* user_input) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  EXPECT_EQ(OSRSetFromUserInput(srs, user_input), OGRERR_NONE);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  std::string out = wkt;
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  return out;
}

bool SameCrs(const std::string& a, const std::string& b) {
  OGRSpatialReferenceH sa = OSRNewSpatialReference(a.c_str());
  OGRSpatialReferenceH sb = OSRNewSpatialReference(b.c_str());
  const bool same = sa != nullptr && sb != nullptr && OSRIsSame(sa, sb);
  OSRDestroySpatialReference(sa);
  OSRDestroySpatialReference(sb);
  return same;
}

// A GeoTIFF written with GDAL directly: `bands` Float64 bands, band b's cell
// i = 100 b + i; `setup` may change the dataset before it is closed.
std::string MakeTiff(const std::string& path, int columns, int rows, int bands, const double gt[6],
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

Raster SampleRaster() {
  Raster r;
  r.columns = 5, r.rows = 4;
  r.geotransform = {1000.0, 2.0, 0.0, 5000.0, 0.0, -2.0};
  r.crs_wkt = Wkt("EPSG:32760");
  for (int i = 0; i < 20; ++i) r.values.push_back(0.25 * i - 1.5);
  r.values[3] = kNaN, r.values[7] = kNaN, r.values[19] = kNaN;
  return r;
}

// --- GeoTIFF round trip ----------------------------------------------------

TEST_F(RasterIoTest, GeoTiffRoundTripKeepsValuesGeotransformCrsAndNodata) {
  const Raster in = SampleRaster();
  const std::string path = Path("a.tif");
  WriteGeoTiff(path, in, "test");
  EXPECT_EQ(Entries(), std::set<std::string>{"a.tif"});  // no temporary, no .aux.xml

  const Raster out = ReadRaster(path);
  EXPECT_EQ(out.columns, 5);
  EXPECT_EQ(out.rows, 4);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(out.geotransform[k], in.geotransform[k]) << k;
  EXPECT_TRUE(SameCrs(out.crs_wkt, in.crs_wkt)) << out.crs_wkt;
  ASSERT_EQ(out.values.size(), 20u);
  for (int i = 0; i < 20; ++i) {
    if (std::isnan(in.values[i])) {
      EXPECT_TRUE(std::isnan(out.values[i])) << i;
    } else {
      EXPECT_EQ(out.values[i], in.values[i]) << i;  // quarters are exact in Float32
    }
  }
  // The file itself: Float32, DEFLATE, nodata -9999 stored in the NaN cells.
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  EXPECT_EQ(GDALGetRasterDataType(band), GDT_Float32);
  const char* compression = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
  EXPECT_STREQ(compression, "DEFLATE");
  int has_nodata = 0;
  EXPECT_EQ(GDALGetRasterNoDataValue(band, &has_nodata), -9999.0);
  EXPECT_TRUE(has_nodata);
  float cell = 0;
  ASSERT_EQ(GDALRasterIO(band, GF_Read, 3, 0, 1, 1, &cell, 1, 1, GDT_Float32, 0, 0), CE_None);
  EXPECT_EQ(cell, -9999.0f);
  GDALClose(ds);
}

TEST_F(RasterIoTest, SamplesSkipNodataAndSitAtCellCentres) {
  WriteGeoTiff(Path("a.tif"), SampleRaster(), "test");
  const Raster raster = ReadRaster(Path("a.tif"));
  std::vector<int64_t> cells;
  const Surface s = RasterToSurface(raster, &cells, 1.0);
  ASSERT_EQ(s.size(), 17u);
  ASSERT_EQ(cells.size(), 17u);
  EXPECT_EQ(s.source, Path("a.tif"));
  size_t k = 0;
  for (int i = 0; i < 20; ++i) {
    if (i == 3 || i == 7 || i == 19) continue;
    const int c = i % 5, r = i / 5;
    EXPECT_EQ(cells[k], i);
    EXPECT_EQ(s.xy[k].x + s.origin[0], 1000.0 + 2.0 * c + 1.0) << i;  // x0 + (c + 1/2) dx
    EXPECT_EQ(s.xy[k].y + s.origin[1], 5000.0 - 2.0 * r - 1.0) << i;
    EXPECT_EQ(s.z[k] + s.origin[2], 0.25 * i - 1.5) << i;
    ++k;
  }
  EXPECT_EQ(RasterToSurface(raster, nullptr).size(), 17u);
}

TEST_F(RasterIoTest, NodataValueAvoidsValuesInTheData) {
  Raster r = SampleRaster();
  r.values[0] = -9999.0;
  r.values[1] = -99999.0;
  WriteGeoTiff(Path("a.tif"), r, "test");
  GDALDatasetH ds = GDALOpen(Path("a.tif").c_str(), GA_ReadOnly);
  int has = 0;
  const double nodata = GDALGetRasterNoDataValue(GDALGetRasterBand(ds, 1), &has);
  GDALClose(ds);
  EXPECT_TRUE(has);
  EXPECT_EQ(nodata, -32768.0);  // the first of -9999, -99999, -32768 that is unused
  const Raster back = ReadRaster(Path("a.tif"));
  EXPECT_EQ(back.values[0], -9999.0);
  EXPECT_EQ(back.values[1], -99999.0);
  EXPECT_TRUE(std::isnan(back.values[3]));
}

TEST_F(RasterIoTest, LargeRastersAreTiled) {
  Raster r;
  r.columns = 600, r.rows = 3;
  r.values.assign(1800, 1.0);
  WriteGeoTiff(Path("big.tif"), r, "test");
  GDALDatasetH ds = GDALOpen(Path("big.tif").c_str(), GA_ReadOnly);
  int bx = 0, by = 0;
  GDALGetBlockSize(GDALGetRasterBand(ds, 1), &bx, &by);
  GDALClose(ds);
  EXPECT_EQ(bx, 256);
  EXPECT_EQ(by, 256);
  EXPECT_EQ(ReadRaster(Path("big.tif")).crs_wkt, "");  // no CRS given, none written
}

// Rasters of several chunks (the values converted and scanned by chunks of
// rows): the nodata value avoids what any chunk holds, the first value
// outside Float32 in row-major order is the one named, and the file's bytes
// do not depend on the threads.
TEST_F(RasterIoTest, LargeRasterWritesTheSameOnAnyThreadCount) {
  Raster r;
  r.columns = 700, r.rows = 300;  // 210,000 cells: several chunks
  r.geotransform = {1000.0, 2.0, 0.0, 5000.0, 0.0, -2.0};
  r.values.resize(static_cast<std::size_t>(r.columns) * r.rows);
  for (std::size_t i = 0; i < r.values.size(); ++i) r.values[i] = 0.001 * static_cast<double>(i % 9973);
  r.values[10] = -99999.0;                    // the first chunk
  r.values[r.values.size() - 5] = -9999.0;    // the last
  r.values[r.values.size() / 2] = kNaN;
  std::string bytes[3];
  for (int threads : {1, 2, 8}) {
    const std::string path = Path("t" + std::to_string(threads) + ".tif");
    WriteGeoTiff(path, r, "test", threads);
    std::ifstream in(path, std::ios::binary);
    std::stringstream contents;
    contents << in.rdbuf();
    bytes[threads == 1 ? 0 : threads == 2 ? 1 : 2] = contents.str();
  }
  EXPECT_EQ(bytes[0], bytes[1]);
  EXPECT_EQ(bytes[0], bytes[2]);
  GDALDatasetH ds = GDALOpen(Path("t1.tif").c_str(), GA_ReadOnly);
  int has = 0;
  EXPECT_EQ(GDALGetRasterNoDataValue(GDALGetRasterBand(ds, 1), &has), -32768.0);
  GDALClose(ds);
  const Raster back = ReadRaster(Path("t2.tif"));
  ASSERT_EQ(back.values.size(), r.values.size());
  for (std::size_t i = 0; i < r.values.size(); ++i) {
    if (std::isnan(r.values[i])) {
      EXPECT_TRUE(std::isnan(back.values[i])) << i;
    } else {
      ASSERT_EQ(back.values[i], static_cast<double>(static_cast<float>(r.values[i]))) << i;
    }
  }
  // Every usual nodata value is data: the first unused step below -9999.
  r.values[20] = -32768.0, r.values[r.values.size() - 20] = std::numeric_limits<float>::lowest();
  r.values[30] = -10000.0;
  WriteGeoTiff(Path("steps.tif"), r, "test", 2);
  ds = GDALOpen(Path("steps.tif").c_str(), GA_ReadOnly);
  EXPECT_EQ(GDALGetRasterNoDataValue(GDALGetRasterBand(ds, 1), &has), -10001.0);
  GDALClose(ds);
  // Two values beyond Float32 in different chunks: the first is named.
  r.values[r.values.size() - 3] = -1e40;
  r.values[250 * 700 + 5] = 1e39;
  EXPECT_EQ(ErrorOf([&] { WriteGeoTiff(Path("bad.tif"), r, "out", 2); }),
            "out: '" + Path("bad.tif") + "': value 9.9999999999999994e+38 at column 5, row 250 does not fit Float32");
  EXPECT_EQ(Entries().count("bad.tif"), 0u);
}

// --- nodata, masks, NaN on reading -----------------------------------------

TEST_F(RasterIoTest, NanInfinityNodataAndMaskCellsAreSkipped) {
  const double gt[6] = {0, 1, 0, 0, 0, -1};
  MakeTiff(Path("m.tif"), 4, 2, 1, gt, [](GDALDatasetH ds) {
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    const double special[3] = {kNaN, HUGE_VAL, -HUGE_VAL};
    ASSERT_EQ(GDALRasterIO(band, GF_Write, 0, 0, 3, 1, const_cast<double*>(special), 3, 1,
                           GDT_Float64, 0, 0),
              CE_None);
    GDALSetRasterNoDataValue(band, 103.0);  // cell 3
    ASSERT_EQ(GDALCreateDatasetMaskBand(ds, GMF_PER_DATASET), CE_None);
    unsigned char mask[8] = {255, 255, 255, 255, 0, 0, 255, 255};  // cells 4, 5 masked out
    ASSERT_EQ(GDALRasterIO(GDALGetMaskBand(band), GF_Write, 0, 0, 4, 2, mask, 4, 2, GDT_Byte, 0, 0),
              CE_None);
  });
  const Raster r = ReadRaster(Path("m.tif"));
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(std::isnan(r.values[i])) << i;
  EXPECT_EQ(r.values[6], 106.0);
  EXPECT_EQ(r.values[7], 107.0);
  EXPECT_EQ(r.non_finite_cells, 3);  // NaN, +inf, -inf; not the nodata cell, not the masked ones
}

TEST_F(RasterIoTest, Float32NodataThatIsNotAFloatStillMatches) {
  // An ESRI .flt grid written by hand: its header's -9999.1 is not a float,
  // the Float32 cell holding it is float(-9999.1).
  WriteText("f.hdr",
            "ncols 3\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
            "NODATA_value -9999.1\nbyteorder LSBFIRST\n");
  std::string bytes;
  for (float v : {1.0f, static_cast<float>(-9999.1), 3.0f}) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int k = 0; k < 4; ++k) bytes += static_cast<char>((bits >> (8 * k)) & 0xff);
  }
  WriteText("f.flt", bytes);
  const Raster r = ReadRaster(Path("f.flt"));
  ASSERT_EQ(r.values.size(), 3u);
  EXPECT_EQ(r.values[0], 1.0);
  EXPECT_TRUE(std::isnan(r.values[1]));
  EXPECT_EQ(r.values[2], 3.0);
}

// --- bands and windows -----------------------------------------------------

TEST_F(RasterIoTest, BandSelection) {
  const double gt[6] = {10, 1, 0, 20, 0, -1};
  const std::string path = MakeTiff(Path("two.tif"), 3, 2, 2, gt);
  RasterReadOptions options;
  options.band = 2;
  const Raster r = ReadRaster(path, options);
  ASSERT_EQ(r.values.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(r.values[i], 200.0 + i);
  EXPECT_EQ(ReadRaster(path).values[5], 105.0);
  options.band = 3;
  EXPECT_EQ(ErrorOf([&] { ReadRaster(path, options); }), path + ": band 3 of 2");
  options.band = 0;
  EXPECT_EQ(ErrorOf([&] { ReadRaster(path, options); }), path + ": band 0 of 2");
}

// A window of several bands of rows (each read on its own GDAL handle):
// every cell as written, nodata, NaN and masked cells in each band, the
// non-finite count summed, on 1, 2 and 8 threads.
TEST_F(RasterIoTest, LargeWindowsReadByBandsOfRowsOnAnyThreadCount) {
  const int columns = 200, rows = 16000;  // 3 bands of rows of about 2^20 cells
  const double gt[6] = {0, 1, 0, 0, 0, -1};
  const int special_rows[3] = {10, 8000, 15990};  // one in each band
  const std::string path = MakeTiff(Path("big.tif"), columns, rows, 1, gt, [&](GDALDatasetH ds) {
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    GDALSetRasterNoDataValue(band, 100.0 + 2 * columns + 5);  // row 2, column 5
    std::vector<unsigned char> mask(static_cast<std::size_t>(columns) * rows, 255);
    for (const int r : special_rows) {
      const double nan = kNaN;
      ASSERT_EQ(GDALRasterIO(band, GF_Write, 7, r, 1, 1, const_cast<double*>(&nan), 1, 1, GDT_Float64, 0, 0),
                CE_None);
      mask[static_cast<std::size_t>(r) * columns + 9] = 0;
    }
    ASSERT_EQ(GDALCreateDatasetMaskBand(ds, GMF_PER_DATASET), CE_None);
    ASSERT_EQ(GDALRasterIO(GDALGetMaskBand(band), GF_Write, 0, 0, columns, rows, mask.data(), columns, rows,
                           GDT_Byte, 0, 0),
              CE_None);
  });
  for (const int threads : {1, 2, 8}) {
    RasterReadOptions options;
    options.threads = threads;
    options.window = {3, 2, 0, 0};  // the bands of rows start at the window's row 2
    const Raster r = ReadRaster(path, options);
    ASSERT_EQ(r.columns, columns - 3);
    ASSERT_EQ(r.rows, rows - 2);
    EXPECT_EQ(r.non_finite_cells, 3) << threads;
    int64_t wrong = 0, missing = 0;
    for (int row = 0; row < r.rows; ++row) {
      for (int column = 0; column < r.columns; ++column) {
        const int fr = row + 2, fc = column + 3;
        const double v = r.values[static_cast<std::size_t>(row) * r.columns + column];
        const bool special = std::count(std::begin(special_rows), std::end(special_rows), fr) > 0;
        if ((special && (fc == 7 || fc == 9)) || (fr == 2 && fc == 5)) {
          missing += std::isnan(v) ? 0 : 1;
        } else if (v != 100.0 + static_cast<double>(static_cast<int64_t>(fr) * columns + fc)) {
          ++wrong;
        }
      }
    }
    EXPECT_EQ(wrong, 0) << threads;
    EXPECT_EQ(missing, 0) << threads;
  }
}

TEST_F(RasterIoTest, WindowReadsASubBlockWithItsOwnGeotransform) {
  const double gt[6] = {100, 0.5, 0, 200, 0, -0.25};
  const std::string path = MakeTiff(Path("w.tif"), 6, 5, 1, gt);
  const Raster full = ReadRaster(path);
  RasterReadOptions options;
  options.window = {2, 1, 3, 2};
  const Raster w = ReadRaster(path, options);
  ASSERT_EQ(w.columns, 3);
  ASSERT_EQ(w.rows, 2);
  EXPECT_EQ(w.geotransform[0], 101.0);
  EXPECT_EQ(w.geotransform[3], 199.75);
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(w.values[r * 3 + c], 100.0 + (r + 1) * 6 + (c + 2));
      EXPECT_EQ(w.CellCentre(c, r).x, full.CellCentre(c + 2, r + 1).x);
      EXPECT_EQ(w.CellCentre(c, r).y, full.CellCentre(c + 2, r + 1).y);
    }
  }
  options.window = {4, 3, 0, 0};  // to the edges
  const Raster corner = ReadRaster(path, options);
  EXPECT_EQ(corner.columns, 2);
  EXPECT_EQ(corner.rows, 2);
  EXPECT_EQ(corner.values.back(), 129.0);
}

TEST_F(RasterIoTest, WindowOutsideTheRasterIsAnError) {
  const double gt[6] = {0, 1, 0, 0, 0, -1};
  const std::string path = MakeTiff(Path("w.tif"), 6, 5, 1, gt);
  const RasterWindow bad[] = {{6, 0, 0, 0}, {0, 5, 0, 0}, {-1, 0, 2, 2}, {0, 0, 7, 1},
                              {4, 0, 3, 1}, {0, 3, 1, 3}, {0, 0, -1, 2}};
  for (const RasterWindow& window : bad) {
    RasterReadOptions options;
    options.window = window;
    const std::string error = ErrorOf([&] { ReadRaster(path, options); });
    EXPECT_TRUE(Contains(error, path + ": window at column "));
    EXPECT_TRUE(Contains(error, "outside the raster (6 x 5 cells)"));
  }
  RasterReadOptions whole;
  whole.window = {0, 0, 6, 5};
  EXPECT_EQ(ReadRaster(path, whole).values.size(), 30u);
}

// --- pixel convention ------------------------------------------------------

TEST_F(RasterIoTest, AsciiGridCornerAndCentreGiveTheSameCellCentres) {
  const std::string body = "cellsize 0.5\nNODATA_value -9999\n1 2 3\n4 -9999 6\n";
  const std::string corner =
      WriteText("corner.asc", "ncols 3\nnrows 2\nxllcorner 100.0\nyllcorner 200.0\n" + body);
  const std::string centre =
      WriteText("centre.asc", "ncols 3\nnrows 2\nxllcenter 100.25\nyllcenter 200.25\n" + body);
  const Surface a = ReadSurface(corner), b = ReadSurface(centre);
  // Row 0 is the top: its centres are at y = 200 + 1.5 * 0.5; cell (1, 1) is nodata.
  const double expected[5][3] = {{100.25, 200.75, 1},
                                 {100.75, 200.75, 2},
                                 {101.25, 200.75, 3},
                                 {100.25, 200.25, 4},
                                 {101.25, 200.25, 6}};
  ASSERT_EQ(a.size(), 5u);
  ASSERT_EQ(b.size(), 5u);
  for (size_t i = 0; i < 5; ++i) {
    for (const Surface* s : {&a, &b}) {
      EXPECT_EQ(s->xy[i].x + s->origin[0], expected[i][0]) << i;
      EXPECT_EQ(s->xy[i].y + s->origin[1], expected[i][1]) << i;
      EXPECT_EQ(s->z[i] + s->origin[2], expected[i][2]) << i;
    }
  }
}

TEST_F(RasterIoTest, PixelIsPointGeoTiffTiePointIsACellCentre) {
  // GDAL is given the area geotransform whose cell (0, 0) is centred at
  // (1000, 2000); with AREA_OR_POINT=Point it stores that centre as the tie point.
  const double gt[6] = {995, 10, 0, 2005, 0, -10};
  const std::string path = MakeTiff(Path("point.tif"), 4, 3, 1, gt, [](GDALDatasetH ds) {
    GDALSetMetadataItem(ds, "AREA_OR_POINT", "Point", nullptr);
  });
  // The raw tie point (what the file says, no half-cell shift) is the centre.
  CPLSetConfigOption("GTIFF_POINT_GEO_IGNORE", "TRUE");
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  CPLSetConfigOption("GTIFF_POINT_GEO_IGNORE", nullptr);
  ASSERT_NE(ds, nullptr);
  double raw[6];
  GDALGetGeoTransform(ds, raw);
  EXPECT_STREQ(GDALGetMetadataItem(ds, "AREA_OR_POINT", nullptr), "Point");
  GDALClose(ds);
  EXPECT_EQ(raw[0], 1000.0);
  EXPECT_EQ(raw[3], 2000.0);
  // Read as usual, cell (0, 0) is centred exactly on the tie point.
  const Raster r = ReadRaster(path);
  EXPECT_EQ(r.CellCentre(0, 0).x, 1000.0);
  EXPECT_EQ(r.CellCentre(0, 0).y, 2000.0);
  EXPECT_EQ(r.CellCentre(3, 2).x, 1030.0);
  EXPECT_EQ(r.CellCentre(3, 2).y, 1980.0);
  const Surface s = ReadSurface(path);
  EXPECT_EQ(s.xy[0].x + s.origin[0], 1000.0);
  EXPECT_EQ(s.xy[0].y + s.origin[1], 2000.0);
}

// --- atomic writes ---------------------------------------------------------

TEST_F(RasterIoTest, WriteIntoMissingDirectoryThrowsAndLeavesNothing) {
  const std::string path = Path("missing/a.tif");
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteGeoTiff(path, SampleRaster(), "flag --output"); }),
                       "flag --output: cannot write '" + path + "': directory"));
  EXPECT_TRUE(Entries().empty());
}

TEST_F(RasterIoTest, FailedWriteLeavesTheExistingFileUnchanged) {
  const std::string path = WriteText("old.tif", "previous contents");
  Raster r = SampleRaster();
  r.values[12] = 1e300;  // fails before any file is made
  const std::string error = ErrorOf([&] { WriteGeoTiff(path, r, "out"); });
  EXPECT_EQ(error, "out: '" + path +
                       "': value 1.0000000000000001e+300 at column 2, row 2 does "
                       "not fit Float32");
  r = SampleRaster();
  r.values.pop_back();
  EXPECT_EQ(ErrorOf([&] { WriteGeoTiff(path, r, "out"); }),
            "out: '" + path + "': raster of 5 x 4 cells has 19 values");
  r = SampleRaster();
  r.crs_wkt = "GEOGCS[nonsense";
  EXPECT_TRUE(Contains(ErrorOf([&] { WriteGeoTiff(path, r, "out"); }), "unreadable CRS"));
  std::ifstream in(path);
  std::stringstream contents;
  contents << in.rdbuf();
  EXPECT_EQ(contents.str(), "previous contents");
  EXPECT_EQ(Entries(), std::set<std::string>{"old.tif"});
  WriteGeoTiff(path, SampleRaster(), "out");  // a successful write replaces it
  EXPECT_EQ(ReadRaster(path).columns, 5);
  EXPECT_EQ(Entries(), std::set<std::string>{"old.tif"});
}

// --- errors ----------------------------------------------------------------

TEST_F(RasterIoTest, ReadErrorsNameTheFileOnOneLine) {
  const std::string text = WriteText("text.tif", "not a raster\n");
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadRaster(text); }), text + ": cannot open as a raster"));
  const std::string missing = Path("missing.tif");
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadRaster(missing); }), missing + ": cannot open"));
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadSurface(missing); }), missing + ": cannot open"));

  const double rotated[6] = {0, 1, 0.1, 0, 0, -1};
  const std::string r = MakeTiff(Path("rot.tif"), 3, 3, 1, rotated);
  EXPECT_EQ(ErrorOf([&] { ReadRaster(r); }),
            r + ": rotated or sheared geotransform (row/column terms 0.10000000000000001, 0) is "
                "not supported; warp it to a north-up grid first");

  Raster empty = SampleRaster();
  empty.values.assign(20, kNaN);
  WriteGeoTiff(Path("nodata.tif"), empty, "test");
  EXPECT_EQ(ErrorOf([&] { ReadSurface(Path("nodata.tif")); }),
            Path("nodata.tif") + ": every cell is nodata");
  // Too few valid cells for a surface: ValidateSurface's message.
  Raster two = SampleRaster();
  two.values.assign(20, kNaN);
  two.values[0] = two.values[1] = 5.0;
  EXPECT_TRUE(Contains(ErrorOf([&] { RasterToSurface(two, nullptr); }), "2 points"));
}

TEST_F(RasterIoTest, ReadSurfaceReadsRastersByExtension) {
  WriteGeoTiff(Path("a.TIF"), SampleRaster(), "test");
  const Surface s = ReadSurface(Path("a.TIF"));
  EXPECT_EQ(s.size(), 17u);
  EXPECT_EQ(s.xy[0].x + s.origin[0], 1001.0);
  EXPECT_EQ(s.xy[0].y + s.origin[1], 4999.0);
  EXPECT_EQ(s.z[0] + s.origin[2], -1.5);
  ReadOptions options;
  options.origin_step = 1000.0;
  EXPECT_EQ(ReadSurface(Path("a.TIF"), options).origin[0], 1000.0);
}

// The grid ReadSurface gives back: the raster's size, georeferencing and
// CRS without its values, its samples' cells on it; on two threads the same
// samples. A point file leaves it as it was.
TEST_F(RasterIoTest, ReadSurfaceGivesTheRastersGrid) {
  const Raster written = SampleRaster();
  WriteGeoTiff(Path("g.tif"), written, "test");
  const Raster read = ReadRaster(Path("g.tif"));
  Raster grid;
  std::string crs;
  ReadOptions two;
  two.threads = 2;
  const Surface s = ReadSurface(Path("g.tif"), two, &crs, &grid);
  EXPECT_EQ(grid.columns, read.columns);
  EXPECT_EQ(grid.rows, read.rows);
  EXPECT_EQ(grid.geotransform, read.geotransform);
  EXPECT_EQ(grid.crs_wkt, read.crs_wkt);
  EXPECT_EQ(crs, read.crs_wkt);
  EXPECT_TRUE(grid.values.empty());
  const Surface plain = ReadSurface(Path("g.tif"));
  ASSERT_EQ(s.size(), plain.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s.z[i], plain.z[i]);
    const RasterCell cell = s.raster_cell[i];
    EXPECT_EQ(s.z[i] + s.origin[2], read.values[static_cast<std::size_t>(cell.row) * read.columns + cell.column]);
  }
  {
    std::ofstream out(Path("p.xyz"));
    out << "0 0 1\n1 0 2\n0 1 3\n";
  }
  Raster untouched;
  untouched.columns = 7;
  ReadSurface(Path("p.xyz"), {}, nullptr, &untouched);
  EXPECT_EQ(untouched.columns, 7);
}

TEST(IsRasterPathTest, Extensions) {
  for (const char* yes : {"a.tif", "b/c.TIFF", "x.vrt", "x.asc", "x.img", "x.bil", "x.hgt",
                          "N36E174.HGT", "x.dem", "x.nc", "x.gpkg", "x.flt", "a.b/c.Tif"}) {
    EXPECT_TRUE(IsRasterPath(yes)) << yes;
  }
  for (const char* no : {"a.xyz", "a.ply", "tif", "a.tif/b", "a.tif.bak", "a", ""}) {
    EXPECT_FALSE(IsRasterPath(no)) << no;
  }
}

}  // namespace
}  // namespace surfreg

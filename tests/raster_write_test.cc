// GDAL rasters, writing: GeoTIFF round trip (values, geotransform, CRS,
// nodata), the nodata choice, tiles, the same bytes on any thread count,
// and atomic writes (nothing partial left on any error).
#include "io/raster_io.h"

#include <gtest/gtest.h>

#include "tests/testing/raster_io_fixture.h"

namespace surfreg {
namespace {

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


}  // namespace
}  // namespace surfreg

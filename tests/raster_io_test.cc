// GDAL rasters, reading: nodata/mask/NaN handling, bands, windows read by
// bands of rows, the pixel-is-area/point convention (against hand-computed
// cell centres) and every error. Fixture files are written by the tests, as
// text (.asc) or through GDAL's own API (independent of the code under test).
#include "io/raster_io.h"

#include <gtest/gtest.h>

#include "io/surface_reader.h"
#include "tests/testing/raster_io_fixture.h"

namespace surfreg {
namespace {

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
  const std::string crs = Wkt("EPSG:32633");
  const std::string path = MakeTiff(Path("big.tif"), columns, rows, 1, gt, [&](GDALDatasetH ds) {
    ASSERT_EQ(GDALSetProjection(ds, crs.c_str()), CE_None);
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
    EXPECT_TRUE(SameCrs(r.crs_wkt, crs)) << threads;  // read beside the rows
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

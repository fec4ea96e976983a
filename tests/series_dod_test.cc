// `series` on raster epochs (tools/series_run.h): the DoD of each
// consecutive pair on the earlier epoch's grid. Three grids of one analytic
// terrain, each offset by a fraction of a cell and lifted by a known
// height; the last has a 3 m mound. The DoDs must show the mound, nothing
// elsewhere, nodata where the earlier epoch has none or the later does not
// reach, and keep the earlier raster's georeferencing; the refusals name
// the key.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/raster_io.h"
#include "measure/input_error.h"
#include "testing/surface_pairs.h"
#include "tools/series_config.h"
#include "tools/series_run.h"

namespace surfreg {
namespace {

// `call` throws an InputError whose message is `message`.
template <typename Call>
void ExpectInputError(Call&& call, const std::string& message) {
  try {
    call();
    ADD_FAILURE() << "no error; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

constexpr double kMound = 3.0, kMoundX = 48, kMoundY = 40, kMoundRadius = 6;

bool InMound(double x, double y, double margin) {
  return std::hypot(x - kMoundX, y - kMoundY) < kMoundRadius + margin;
}

// A 1 m grid of columns × rows whose top-left corner is (left, top), heights
// of the terrain plus `lift` (and the mound when `mound`); `holes` cells of
// nodata at fixed places.
Raster Epoch(double left, double top, int columns, int rows, double lift, bool mound, bool holes) {
  Raster r;
  r.columns = columns, r.rows = rows;
  r.geotransform = {left, 1.0, 0.0, top, 0.0, -1.0};
  r.crs_wkt = "EPSG:32633";
  r.values.resize(static_cast<std::size_t>(columns) * rows);
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      const Point2 c = r.CellCentre(column, row);
      double z = testing::SmoothTerrain(c.x, c.y) + lift;
      if (mound && InMound(c.x, c.y, 0)) z += kMound;
      r.values[static_cast<std::size_t>(row) * columns + column] = z;
    }
  }
  if (holes) {
    for (int k = 0; k < 12; ++k) r.values[static_cast<std::size_t>(5 + 3 * k) * columns + 7 + 2 * k] = std::nan("");
  }
  return r;
}

class SeriesDodTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "series_dod_test_XXXXXX";
    ASSERT_NE(mkdtemp(&pattern[0]), nullptr);
    dir_ = pattern;
    std::filesystem::create_directory(dir_ + "/dod");
    WriteGeoTiff(Path("e0.tif"), Epoch(10, 70, 60, 60, 0.0, false, true), "test");
    WriteGeoTiff(Path("e1.tif"), Epoch(18.3, 74.6, 60, 60, 0.25, false, false), "test");
    WriteGeoTiff(Path("e2.tif"), Epoch(24.7, 67.2, 60, 60, -0.15, true, false), "test");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  SeriesConfig Config() const {
    SeriesConfig config;
    ApplySeriesArguments({Path("e0.tif"), Path("e1.tif"), Path("e2.tif")}, &config);
    ApplySeriesSetting("dod_dir", dir_ + "/dod", "test", &config);
    ApplySeriesSetting("stable", "auto", "test", &config);
    return config;
  }

  std::string dir_;
};

TEST_F(SeriesDodTest, EachConsecutivePairsDodLiesOnTheEarlierGridAndShowsTheChange) {
  SeriesConfig config = Config();
  FinishSeriesConfig(&config);
  const SeriesRun run = AlignSeriesFiles(config, std::nullopt, nullptr);
  ASSERT_EQ(run.consecutive.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const ConsecutiveChange& change = run.consecutive[k];
    EXPECT_EQ(change.dod, Path("dod/e" + std::to_string(k) + "_to_e" + std::to_string(k + 1) + ".tif"));
    EXPECT_NE(run.json.find("\"dod\": \"" + change.dod + "\""), std::string::npos);
    const Raster earlier = ReadRaster(Path("e" + std::to_string(k) + ".tif"));
    const Raster later = ReadRaster(Path("e" + std::to_string(k + 1) + ".tif"));
    const Raster dod = ReadRaster(change.dod);
    ASSERT_EQ(dod.columns, earlier.columns);
    ASSERT_EQ(dod.rows, earlier.rows);
    EXPECT_EQ(dod.geotransform, earlier.geotransform);
    EXPECT_FALSE(dod.crs_wkt.empty());
    // The later grid's cell centres' hull, shrunk by a cell: inside, the
    // DoD is defined; well outside, nodata.
    const double l0 = later.geotransform[0], t0 = later.geotransform[3];
    const double l1 = l0 + later.columns, b1 = t0 - later.rows;
    int64_t defined = 0, in_mound = 0;
    std::vector<double> dz_values;
    for (int row = 0; row < dod.rows; ++row) {
      for (int column = 0; column < dod.columns; ++column) {
        const double value = dod.values[static_cast<std::size_t>(row) * dod.columns + column];
        const double source = earlier.values[static_cast<std::size_t>(row) * earlier.columns + column];
        const Point2 c = dod.CellCentre(column, row);
        if (!std::isfinite(source)) {
          EXPECT_FALSE(std::isfinite(value)) << "a nodata cell of the earlier epoch, " << column << " " << row;
          continue;
        }
        const bool inside = c.x > l0 + 1.5 && c.x < l1 - 1.5 && c.y < t0 - 1.5 && c.y > b1 + 1.5;
        const bool outside = c.x < l0 - 0.5 || c.x > l1 + 0.5 || c.y > t0 + 0.5 || c.y < b1 - 0.5;
        if (outside) {
          EXPECT_FALSE(std::isfinite(value)) << "beyond the later epoch, " << column << " " << row;
          continue;
        }
        if (!inside) continue;
        ASSERT_TRUE(std::isfinite(value)) << column << " " << row;
        ++defined;
        dz_values.push_back(value);
        // The mound (k = 1 only) where the later epoch has it whole; the
        // terrain's interpolation error is a few centimetres.
        if (k == 1 && InMound(c.x, c.y, -1.5)) {
          ++in_mound;
          EXPECT_NEAR(value, kMound, 0.1) << column << " " << row;
        } else if (k == 0 || !InMound(c.x, c.y, 1.5)) {
          EXPECT_NEAR(value, 0.0, 0.1) << "k " << k << " at " << column << " " << row;
        }
      }
    }
    EXPECT_GT(defined, 1500);
    if (k == 1) {
      EXPECT_GT(in_mound, 50);
    }
    // The JSON's dz statistics are those of the DoD's values (its count at
    // least the cells checked, its median theirs within the noise).
    EXPECT_GE(change.dz.count, defined);
    EXPECT_NEAR(change.dz.median, 0.0, 0.02);
  }
}

TEST_F(SeriesDodTest, RefusalsNameTheKey) {
  SeriesConfig config = Config();
  ApplySeriesSetting("dod_dir", dir_ + "/missing", "flag '--dod_dir'", &config);
  ExpectInputError([&] { FinishSeriesConfig(&config); }, "flag '--dod_dir': no such folder '" + dir_ + "/missing'");
  // A cloud before the last epoch: its DoD has no grid.
  {
    FILE* f = std::fopen(Path("c.xyz").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("0 0 0\n1 0 0\n0 1 0\n", f);
    std::fclose(f);
  }
  SeriesConfig cloud;
  ApplySeriesArguments({Path("e0.tif"), Path("c.xyz"), Path("e2.tif")}, &cloud);
  ApplySeriesSetting("dod_dir", dir_ + "/dod", "flag '--dod_dir'", &cloud);
  ExpectInputError([&] { FinishSeriesConfig(&cloud); },
                   "flag '--dod_dir': epoch 1 (" + Path("c.xyz") +
                       ") is not a raster; the DoD of 1-2 is drawn on the earlier epoch's grid");
  // Surfaces given instead of files: no rasters to draw the DoDs on.
  ExpectInputError(
      [&] {
        SeriesConfig given = Config();
        FinishSeriesConfig(&given);
        AlignSeriesFiles(given, std::vector<Surface>(3), nullptr);
      },
      "test: the DoDs are drawn on the epochs' raster files; give the files, not surfaces");
  // A DoD over an input is refused.
  SeriesConfig over;
  std::filesystem::copy_file(Path("e0.tif"), Path("dod/a.tif"));
  std::filesystem::copy_file(Path("e2.tif"), Path("dod/a_to_e1.tif"));
  ApplySeriesArguments({Path("dod/a.tif"), Path("e1.tif"), Path("dod/a_to_e1.tif")}, &over);
  ApplySeriesSetting("dod_dir", dir_ + "/dod", "flag '--dod_dir'", &over);
  ExpectInputError([&] { FinishSeriesConfig(&over); },
                   "flag '--dod_dir': the DoD " + Path("dod/a_to_e1.tif") + " would be written over an epoch");
}

}  // namespace
}  // namespace surfreg

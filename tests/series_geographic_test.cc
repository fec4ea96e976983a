// `series` on epochs in longitude and latitude (terrain/series_epochs.h):
// brought into one metric frame as `align` brings two, solved there. Three
// epochs of an analytic terrain placed in UTM zone 33N, each moved by its
// own known motion (in UTM metres), written as lon/lat clouds: the series in
// the UTM frame must recover those motions; in a local ENU frame the epochs
// must still end on one another. Mixed CRSs are refused naming both epochs.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/raster_io.h"
#include "measure/input_error.h"
#include "terrain/geo_frame.h"
#include "testing/surface_pairs.h"
#include "tools/series_config.h"
#include "tools/series_run.h"

namespace surfreg {
namespace {

constexpr double kEasting = 500000, kNorthing = 4500000;  // the terrain's corner in UTM 33N

double Terrain(double east, double north) {
  return 200.0 + testing::SmoothTerrain(east - kEasting, north - kNorthing);
}

GeoFrame Utm33() {
  GeoFrame frame;
  frame.kind = GeoFrame::kUtm;
  frame.zone = 33;
  frame.northp = true;
  return frame;
}

// `call` throws an InputError whose message contains every one of `parts`.
template <typename Call>
void ExpectInputErrorWith(Call&& call, const std::vector<std::string>& parts) {
  try {
    call();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    for (const std::string& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

class SeriesGeographicTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "series_geographic_test_XXXXXX";
    ASSERT_NE(mkdtemp(&pattern[0]), nullptr);
    dir_ = pattern;
    const Crs lonlat = ParseCrs("EPSG:4326", "test");
    for (int k = 0; k < 3; ++k) {
      std::vector<std::array<double, 3>> points = testing::SampleUniform(
          Terrain, 4000, kEasting, kEasting + 100, kNorthing, kNorthing + 100, 11 + k);
      centroids_.push_back(testing::Centroid(points));
      truths_.push_back(k == 0 ? Eigen::Matrix4d::Identity().eval()
                               : testing::TrueMotion(Eigen::Vector3d(0.3, -0.2 * k, 1.0), 0.4 * k,
                                                     Eigen::Vector3d(0.8 * k, -0.5, 0.1 * k),
                                                     centroids_.back()));
      points = testing::MoveByInverse(points, truths_.back());
      centroids_.back() = testing::Centroid(points);
      PointsFromFrame(Utm33(), lonlat, &points);  // east, north, h -> lon, lat, h
      std::FILE* file = std::fopen(Path(k).c_str(), "w");
      ASSERT_NE(file, nullptr);
      for (const auto& p : points) std::fprintf(file, "%.12f %.12f %.6f\n", p[0], p[1], p[2]);
      std::fclose(file);
    }
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(int k) const { return dir_ + "/e" + std::to_string(k) + ".xyz"; }

  SeriesRun Run(const std::string& frame) const {
    SeriesConfig config;
    ApplySeriesArguments({Path(0), Path(1), Path(2)}, &config);
    ApplySeriesSetting("crs", "EPSG:4326", "test", &config);
    ApplySeriesSetting("frame", frame, "test", &config);
    FinishSeriesConfig(&config);
    return AlignSeriesFiles(config, std::nullopt, nullptr);
  }

  std::string dir_;
  std::vector<Eigen::Matrix4d> truths_;     // epoch k -> epoch 0, UTM metres
  std::vector<Eigen::Vector3d> centroids_;  // of each epoch as written, UTM metres
};

TEST_F(SeriesGeographicTest, LonLatEpochsAreSolvedInUtmAndRecoverTheirMotions) {
  const SeriesRun run = Run("auto");
  EXPECT_EQ(run.frame.kind, GeoFrame::kUtm);
  EXPECT_EQ(run.frame.zone, 33);
  EXPECT_TRUE(run.frame.northp);
  EXPECT_EQ(run.units, "m");
  EXPECT_NE(run.json.find("\"frame\": \"UTM zone 33N (WGS 84"), std::string::npos);
  ASSERT_EQ(run.result.epochs.size(), 3u);
  EXPECT_TRUE(run.result.epochs[0].matrix.isIdentity(0.0));
  for (int k = 1; k < 3; ++k) {
    const testing::MotionError error = testing::CompareMotions(run.result.epochs[k].matrix, truths_[k], centroids_[k]);
    // Samples ~1.6 m apart on a noise-free terrain; motions of 0.4-0.8 degrees and ~1 m.
    EXPECT_LT(error.rotation_deg, 0.01) << "epoch " << k;
    EXPECT_LT(error.translation, 0.01) << "epoch " << k;
  }
  for (const ConsecutiveChange& change : run.consecutive) EXPECT_LT(change.measure.mean_abs_dz, 0.01);
}

TEST_F(SeriesGeographicTest, InALocalEnuFrameTheEpochsEndOnOneAnother) {
  const SeriesRun run = Run("enu");
  EXPECT_EQ(run.frame.kind, GeoFrame::kEnu);
  EXPECT_NE(run.json.find("\"frame\": \"local ENU about 40."), std::string::npos);
  for (const SeriesEpoch& epoch : run.result.epochs) EXPECT_EQ(VerdictName(epoch.verdict), std::string("converged_improved"));
  for (const ConsecutiveChange& change : run.consecutive) EXPECT_LT(change.measure.mean_abs_dz, 0.01);
}

TEST_F(SeriesGeographicTest, EpochsInAProjectedAndAGeographicCrsAreRefusedNamingBoth) {
  Raster projected;
  projected.columns = projected.rows = 20;
  projected.geotransform = {kEasting, 5.0, 0.0, kNorthing + 100, 0.0, -5.0};
  projected.crs_wkt = "EPSG:32633";
  projected.values.assign(400, 200.0);
  const std::string tif = dir_ + "/p.tif";
  WriteGeoTiff(tif, projected, "test");
  SeriesConfig config;
  ApplySeriesArguments({tif, Path(1), Path(2)}, &config);
  ApplySeriesSetting("crs", "EPSG:4326", "test", &config);
  FinishSeriesConfig(&config);
  ExpectInputErrorWith([&] { AlignSeriesFiles(config, std::nullopt, nullptr); },
                       {"epoch 0 (" + tif + ")", "epoch 1 (" + Path(1) + ")",
                        "one is projected, the other geographic"});
}

TEST_F(SeriesGeographicTest, AnEpochWithoutACrsAmongLonLatOnesIsRefused) {
  Raster lonlat;
  lonlat.columns = lonlat.rows = 20;
  lonlat.geotransform = {15.0, 1e-5, 0.0, 40.6, 0.0, -1e-5};
  lonlat.crs_wkt = "EPSG:4326";
  lonlat.values.assign(400, 200.0);
  const std::string tif = dir_ + "/g.tif";
  WriteGeoTiff(tif, lonlat, "test");
  SeriesConfig config;
  ApplySeriesArguments({tif, Path(1)}, &config);  // the cloud's CRS not given
  FinishSeriesConfig(&config);
  ExpectInputErrorWith([&] { AlignSeriesFiles(config, std::nullopt, nullptr); },
                       {"epoch 1 (" + Path(1) + ")", "has no CRS", "key 'crs'"});
}

}  // namespace
}  // namespace surfreg

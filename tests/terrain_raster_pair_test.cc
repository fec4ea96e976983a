// `surfreg measure` of two DEM files on one grid (terrain/terrain_measure.h):
// the compact path (the rasters' heights alone, measure/raster_pair.h)
// gives the general path's numbers, dz statistics and DoD; the pairs it
// leaves to surfaces (a geographic CRS, σ) still measure; its errors are
// the surfaces' errors, named by the key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "io/raster_io.h"
#include "measure/input_error.h"
#include "terrain/terrain_measure.h"

namespace surfreg {
namespace {

class TerrainRasterPairTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/terrain_raster_pair_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  // A 60 x 50 DEM of 10 m cells at UTM-sized coordinates, with a hole;
  // `shift` cells to the east and `change` added to B.
  std::string Write(const std::string& name, int shift, double change, const std::string& crs,
                    double x0 = 500000.0, double y0 = 4000000.0, double cell = 10.0) {
    Raster r;
    r.columns = 60, r.rows = 50;
    r.geotransform = {x0 + cell * shift, cell, 0.0, y0, 0.0, -cell};
    r.crs_wkt = crs;
    for (int row = 0; row < r.rows; ++row) {
      for (int column = 0; column < r.columns; ++column) {
        const int c = column + shift;
        const bool hole = (c - 20) * (c - 20) + (row - 30) * (row - 30) < 20;
        r.values.push_back(
            hole ? std::nan("")
                 : 300.0 + 3.0 * std::sin(0.2 * c) * std::cos(0.15 * row) +
                       change * std::exp(-((c - 40) * (c - 40) + (row - 20) * (row - 20)) / 50.0));
      }
    }
    WriteGeoTiff(Path(name), r, "test");
    return Path(name);
  }

  std::string dir_;
};

constexpr const char* kUtm33 = "EPSG:32633";

class TerrainRasterPairOffsetTest : public TerrainRasterPairTest, public ::testing::WithParamInterface<double> {};

// B three cells east (one grid), or also a fraction of a cell off A's
// lattice (offset grids).
TEST_P(TerrainRasterPairOffsetTest, CompactMeasureEqualsTheGeneralPathAndItsDod) {
  TerrainRequest request;
  request.reference = Write("a.tif", 0, 0.0, kUtm33);
  const double fraction = GetParam();
  request.moving = Write("b.tif", 3, 2.5, kUtm33, 500000.0 + 10.0 * fraction, 4000000.0 - 6.1 * fraction);
  request.terrain.lod = 0.4;
  MeasureOptions options;
  options.detect_change = true;
  request.terrain.dod = Path("compact.tif");
  const TerrainMeasure compact = MeasureTerrain(request, options);
  MeasureOptions general_options = options;
  general_options.grid_shortcut = false;
  request.terrain.dod = Path("general.tif");
  const TerrainMeasure general = MeasureTerrain(request, general_options);
  EXPECT_TRUE(compact.from_heights);
  EXPECT_FALSE(general.from_heights);
  const auto near = [](double x, double y) {
    return std::fabs(x - y) <= 1e-12 * std::max(1.0, std::fabs(x));
  };
  EXPECT_TRUE(near(compact.summary.rho_d, general.summary.rho_d));
  EXPECT_TRUE(near(compact.summary.rho_d_axial, general.summary.rho_d_axial));
  EXPECT_TRUE(near(compact.summary.fill_detected, general.summary.fill_detected));
  EXPECT_TRUE(near(compact.summary.cut_area, general.summary.cut_area));
  EXPECT_EQ(compact.summary.n_overlap_nodes, general.summary.n_overlap_nodes);
  EXPECT_GT(compact.summary.fill_detected, 0.0);
  EXPECT_TRUE(near(compact.dz.median, general.dz.median));
  EXPECT_TRUE(near(compact.dz.nmad, general.dz.nmad));
  EXPECT_EQ(compact.dz.count, general.dz.count);
  EXPECT_EQ(compact.frame.Describe(), general.frame.Describe());
  EXPECT_EQ(compact.crs_b.name, general.crs_b.name);
  EXPECT_TRUE(compact.summary.dz_b.empty());
  EXPECT_TRUE(compact.summary.node_area_a.empty());  // no σ: no budget
  const Raster dod_compact = ReadRaster(Path("compact.tif")),
               dod_general = ReadRaster(Path("general.tif"));
  ASSERT_EQ(dod_compact.values.size(), dod_general.values.size());
  int valid = 0;
  for (std::size_t k = 0; k < dod_compact.values.size(); ++k) {
    ASSERT_EQ(std::isnan(dod_compact.values[k]), std::isnan(dod_general.values[k])) << k;
    if (std::isnan(dod_compact.values[k])) continue;
    ASSERT_NEAR(dod_compact.values[k], dod_general.values[k], 1e-6) << k;
    ++valid;
  }
  EXPECT_EQ(valid, compact.dz.count);  // A's nodes in Ω (on offset grids Ω has B's too)
  if (fraction == 0.0) {
    EXPECT_EQ(valid, compact.summary.n_overlap_nodes);
  }
}

INSTANTIATE_TEST_SUITE_P(OneGridAndOffset, TerrainRasterPairOffsetTest, ::testing::Values(0.0, 0.37));

// The DoD's blocks are compressed on the measure's threads: the file's
// bytes do not depend on how many.
TEST_F(TerrainRasterPairTest, DodFileIsTheSameBytesOnOneAndThreeThreads) {
  TerrainRequest request;
  request.reference = Write("a.tif", 0, 0.0, kUtm33);
  request.moving = Write("b.tif", 3, 2.5, kUtm33);
  std::string bytes[2];
  for (int k = 0; k < 2; ++k) {
    MeasureOptions options;
    options.threads = k == 0 ? 1 : 3;
    request.terrain.dod = Path("dod" + std::to_string(k) + ".tif");
    MeasureTerrain(request, options);
    std::FILE* f = std::fopen(request.terrain.dod.c_str(), "rb");
    ASSERT_NE(f, nullptr);
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, f)) > 0;) bytes[k].append(buffer, n);
    std::fclose(f);
  }
  EXPECT_GT(bytes[0].size(), 1000u);
  EXPECT_EQ(bytes[0], bytes[1]);
}

TEST_F(TerrainRasterPairTest, PairsLeftToSurfacesStillMeasure) {
  TerrainRequest request;
  request.reference = Write("a.tif", 0, 0.0, kUtm33);
  request.moving = Write("b.tif", 3, 2.5, kUtm33);
  MeasureOptions options;
  const TerrainMeasure plain = MeasureTerrain(request, options);
  // σ: the budget needs the surfaces (and keeps the node areas).
  request.terrain.sigma_reference = "0.1";
  const TerrainMeasure with_sigma = MeasureTerrain(request, options);
  EXPECT_TRUE(plain.from_heights);
  EXPECT_FALSE(with_sigma.from_heights);
  EXPECT_TRUE(with_sigma.uncertainty.active);
  EXPECT_FALSE(with_sigma.summary.node_area_a.empty());
  EXPECT_NEAR(with_sigma.summary.rho_d, plain.summary.rho_d, 1e-12 * plain.summary.rho_d);
  // Another cell size: the general path.
  request.terrain.sigma_reference = "";
  Raster finer = ReadRaster(request.moving);
  finer.geotransform[1] = 9.0;
  WriteGeoTiff(Path("finer.tif"), finer, "test");
  request.moving = Path("finer.tif");
  const TerrainMeasure finer_measure = MeasureTerrain(request, options);
  EXPECT_FALSE(finer_measure.from_heights);
  EXPECT_GT(finer_measure.summary.rho_d, 0.0);
  // Geographic rasters: their samples go to a metric frame.
  request.reference = Write("ga.tif", 0, 0.0, "EPSG:4326", 15.0, 45.0, 1e-4);
  request.moving = Write("gb.tif", 3, 2.5, "EPSG:4326", 15.0, 45.0, 1e-4);
  EXPECT_FALSE(MeasureTerrain(request, options).from_heights);
}

TEST_F(TerrainRasterPairTest, ErrorsAreTheSurfacesErrorsNamedByTheKey) {
  TerrainRequest request;
  request.reference = Write("a.tif", 0, 0.0, kUtm33);
  Raster empty = ReadRaster(request.reference);
  for (double& v : empty.values) v = std::nan("");
  empty.values[0] = 1.0;  // one valid cell, written as a raster WriteGeoTiff accepts
  WriteGeoTiff(Path("empty.tif"), empty, "test");
  request.moving = Path("empty.tif");
  request.origin["moving"] = "argument B";
  std::string message;
  try {
    MeasureTerrain(request, MeasureOptions());
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_EQ(message.rfind("argument B: ", 0), 0u) << message;
  EXPECT_NE(message.find("empty.tif"), std::string::npos) << message;
  // Apart: no overlap, Measure's message.
  request.moving = Write("apart.tif", 200, 0.0, kUtm33);
  message.clear();
  try {
    MeasureTerrain(request, MeasureOptions());
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("do not overlap"), std::string::npos) << message;
}

}  // namespace
}  // namespace surfreg

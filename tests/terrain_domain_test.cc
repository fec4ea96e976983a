// Terrain change over the data domain (issue 20): a reference DEM and a
// moving DEM of the same ground on the same grid, the moving one with nodata
// holes (single pixels, small blocks, a void strip) and known vertical
// offsets by column. Ω is then the moving raster's complete cells, d is
// linear on each of them, and the DoD, the dz statistics and cut/fill have
// closed forms computed here cell by cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "measure/dz_statistics.h"
#include "tests/testing/file_checks.h"
#include "tools/align_config.h"
#include "io/raster_io.h"
#include "terrain/terrain.h"

namespace surfreg {
namespace {

constexpr int kColumns = 60, kRows = 50;
constexpr double kDx = 2.0, kDy = 3.0;  // rectangular cells, north-up
constexpr double kLod = 0.2;

// The offset of the moving survey in column c: -0.25, 0, +0.5 m. Exact in
// Float32, as are the heights (multiples of 1/64), so d is exactly it.
double Offset(int column) { return column < 20 ? -0.25 : column < 40 ? 0.0 : 0.5; }

double Ground(int column, int row) {
  const double x = column * kDx, y = row * kDy;
  return std::round(64 * (120 + 8 * std::sin(x / 17) * std::cos(y / 23) + 0.05 * x)) / 64;
}

std::set<std::pair<int, int>> Holes() {
  std::set<std::pair<int, int>> holes = {{5, 5}, {17, 33}, {44, 12}, {59, 20}, {0, 0}, {12, 49}};
  for (int c = 25; c < 27; ++c) {
    for (int r = 40; r < 42; ++r) holes.insert({c, r});  // 2 x 2
  }
  for (int c = 50; c < 53; ++c) {
    for (int r = 5; r < 7; ++r) holes.insert({c, r});  // 3 x 2
  }
  for (int c = 30; c < 33; ++c) {
    for (int r = 8; r < 43; ++r) {
      if (!(c == 31 && r == 25)) holes.insert({c, r});  // a strip, one lone sample in it
    }
  }
  return holes;
}

Raster Grid(bool moving, const std::set<std::pair<int, int>>& holes) {
  Raster raster;
  raster.columns = kColumns;
  raster.rows = kRows;
  raster.geotransform = {500000.0, kDx, 0.0, 4000000.0 + kRows * kDy, 0.0, -kDy};
  raster.values.resize(kColumns * kRows);
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c < kColumns; ++c) {
      const bool hole = moving && holes.count({c, r}) > 0;
      raster.values[r * kColumns + c] =
          hole ? std::nan("") : Ground(c, r) + (moving ? Offset(c) : 0.0);
    }
  }
  return raster;
}

// ∫ of d over {d > lod} (sign +1) or of |d| over {d < -lod} (sign -1) on the
// unit interval, d linear from d0 to d1; and the length of that part.
std::pair<double, double> Beyond(double d0, double d1, double lod, int sign) {
  d0 *= sign, d1 *= sign;  // now: where d > lod
  if (d0 <= lod && d1 <= lod) return {0, 0};
  if (d0 > lod && d1 > lod) return {0.5 * (d0 + d1), 1};
  const double u = (lod - d0) / (d1 - d0);  // d = lod there
  const double length = d1 > d0 ? 1 - u : u;
  const double far = d1 > d0 ? d1 : d0;
  return {length * 0.5 * (lod + far), length};
}

struct Expected {
  std::vector<bool> in_omega;  // per cell (row-major): the centre is in Ω
  std::vector<double> dz;      // finite where in_omega
  double area = 0, signed_volume = 0, above = 0, below = 0;
  double fill = 0, cut = 0, fill_area = 0, cut_area = 0;
};

Expected Cellwise(const std::set<std::pair<int, int>>& holes) {
  auto has = [&](int c, int r) {
    return c >= 0 && r >= 0 && c < kColumns && r < kRows && holes.count({c, r}) == 0;
  };
  // Cell (c, r) of the samples' lattice: samples (c..c+1, r..r+1) all valid.
  auto complete = [&](int c, int r) {
    return has(c, r) && has(c + 1, r) && has(c, r + 1) && has(c + 1, r + 1);
  };
  Expected e;
  e.in_omega.assign(kColumns * kRows, false);
  e.dz.assign(kColumns * kRows, std::nan(""));
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c < kColumns; ++c) {
      // The reference's sample is the moving one's vertex: in Ω iff it is a
      // corner of one of the moving raster's complete cells.
      const bool in = has(c, r) && (complete(c, r) || complete(c - 1, r) || complete(c, r - 1) ||
                                    complete(c - 1, r - 1));
      e.in_omega[r * kColumns + c] = in;
      if (in) e.dz[r * kColumns + c] = Offset(c);
      if (!complete(c, r)) continue;
      // d is linear across the cell (it depends on the column only).
      const double cell = kDx * kDy, d0 = Offset(c), d1 = Offset(c + 1);
      e.area += cell;
      e.signed_volume += cell * 0.5 * (d0 + d1);
      e.above += cell * Beyond(d0, d1, 0, +1).first;
      e.below += cell * Beyond(d0, d1, 0, -1).first;
      const auto fill = Beyond(d0, d1, kLod, +1), cut = Beyond(d0, d1, kLod, -1);
      e.fill += cell * fill.first, e.fill_area += cell * fill.second;
      e.cut += cell * cut.first, e.cut_area += cell * cut.second;
    }
  }
  return e;
}

class TerrainDomainTest : public ::testing::Test {
 protected:
  void SetUp() override {
    reference_ = dir_.path() + "/reference.tif";
    moving_ = dir_.path() + "/moving.tif";
    WriteGeoTiff(reference_, Grid(false, holes_), "reference");
    WriteGeoTiff(moving_, Grid(true, holes_), "moving");
  }

  // align's terrain analysis at the identity motion; returns the DoD read back.
  Raster Analyse(DomainKind kind, TerrainReport* report, bool lod_given = true) {
    AlignConfig config;
    config.reference = reference_;
    config.moving = moving_;
    if (lod_given) {
      config.terrain.lod = kLod;
      config.origin["lod"] = "test's lod";  // given, not measured on the stable terrain
    }
    config.terrain.dod = dir_.path() + (kind == DomainKind::kData ? "/dod.tif" : "/dod_hull.tif");
    config.options.domain.kind = kind;
    const TerrainInputs inputs = ReadTerrainInputs(config);
    EXPECT_TRUE(inputs.reference.raster_grid() && inputs.moving.raster_grid());
    AlignResult identity;
    identity.matrix.setIdentity();
    *report = AnalyseTerrain(config, inputs, identity);
    WriteTerrainOutputs(config, inputs, *report);
    return ReadRaster(config.terrain.dod);
  }

  testing::TempDir dir_;
  std::set<std::pair<int, int>> holes_ = Holes();
  std::string reference_, moving_;
};

TEST_F(TerrainDomainTest, DodStatisticsAndCutFillAreOverOmega) {
  const Expected e = Cellwise(holes_);
  TerrainReport report;
  const Raster dod = Analyse(DomainKind::kData, &report);
  ASSERT_EQ(dod.columns, kColumns);
  ASSERT_EQ(dod.rows, kRows);
  int nodata = 0;
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c < kColumns; ++c) {
      const int k = r * kColumns + c;
      // Rows run north to south in the raster, as in the lattice here.
      const double value = dod.values[k];
      EXPECT_EQ(std::isnan(value), !e.in_omega[k]) << "cell " << c << ", " << r;
      if (holes_.count({c, r})) {
        EXPECT_TRUE(std::isnan(value)) << "hole " << c << ", " << r;
      }
      if (!std::isnan(value)) {
        EXPECT_EQ(value, Offset(c)) << c << ", " << r;
      }
      nodata += std::isnan(value);
    }
  }
  EXPECT_GT(nodata, static_cast<int>(holes_.size()));  // the lone sample, and corners like it
  EXPECT_TRUE(std::isnan(dod.values[25 * kColumns + 31])) << "the lone sample in the strip";

  // dz statistics over Ω (every sample is stable: no mask).
  const MeasureSummary& s = report.after;
  const DzStatistics& st = report.stable_after;
  std::vector<double> dz;
  for (double v : e.dz) {
    if (!std::isnan(v)) dz.push_back(v);
  }
  std::sort(dz.begin(), dz.end());
  const double n = static_cast<double>(dz.size());
  double sum = 0, squares = 0;
  for (double v : dz) sum += v, squares += v * v;
  const double mean = sum / n;
  double variance = 0;
  for (double v : dz) variance += (v - mean) * (v - mean);
  EXPECT_EQ(st.count, static_cast<int64_t>(dz.size()));
  EXPECT_NEAR(st.mean, mean, 1e-9);
  EXPECT_NEAR(st.median,
              dz.size() % 2 ? dz[dz.size() / 2] : 0.5 * (dz[dz.size() / 2 - 1] + dz[dz.size() / 2]),
              1e-9);
  EXPECT_NEAR(st.stddev, std::sqrt(variance / (n - 1)), 1e-9);
  EXPECT_NEAR(st.rmse, std::sqrt(squares / n), 1e-9);
  EXPECT_NEAR(st.min, -0.25, 1e-9);
  EXPECT_NEAR(st.max, 0.5, 1e-9);
  const DzStatistics direct = ComputeDzStatistics(e.dz);
  EXPECT_NEAR(st.nmad, direct.nmad, 1e-9);
  EXPECT_NEAR(st.le90, direct.le90, 1e-9);

  // Cut and fill: exact on the overlay, so to rounding.
  const double tolerance = 1e-9 * e.area;
  EXPECT_NEAR(s.overlap_area, e.area, tolerance);
  EXPECT_NEAR(s.signed_volume, e.signed_volume, tolerance);
  EXPECT_NEAR(s.volume_above, e.above, tolerance);
  EXPECT_NEAR(s.volume_below, e.below, tolerance);
  EXPECT_NEAR(s.fill_detected, e.fill, tolerance);
  EXPECT_NEAR(s.cut_detected, e.cut, tolerance);
  EXPECT_NEAR(s.fill_area, e.fill_area, tolerance);
  EXPECT_NEAR(s.cut_area, e.cut_area, tolerance);
  EXPECT_NEAR(s.domain_area_b, e.area, tolerance);  // the reference covers it all
  EXPECT_NEAR(s.domain_area_a, (kColumns - 1) * (kRows - 1) * kDx * kDy, tolerance);
  EXPECT_GT(s.excluded_area_b, 0.0);
}

// Over the hulls the holes are bridged: the same cells get (invented) values.
// No lod given: the level of detection is 1.96 × the NMAD of dz on the
// stable terrain, and cut/fill are counted beyond it.
TEST_F(TerrainDomainTest, LevelOfDetectionFromTheStableTerrainsNoise) {
  TerrainReport given, measured;
  Analyse(DomainKind::kData, &given);
  Analyse(DomainKind::kData, &measured, /*lod_given=*/false);
  EXPECT_EQ(given.lod, kLod);
  EXPECT_EQ(given.lod_source, "lod");
  ASSERT_GT(measured.stable_after.nmad, 0);
  EXPECT_DOUBLE_EQ(measured.lod, kAutoLodSigmas * measured.stable_after.nmad);
  EXPECT_EQ(measured.lod_source, "1.96 x NMAD of dz on stable terrain");
  EXPECT_DOUBLE_EQ(measured.after.level_of_detection, measured.lod);
  EXPECT_DOUBLE_EQ(measured.before.level_of_detection, measured.lod);
  // Beyond a larger threshold, no more detected area.
  if (measured.lod > kLod) {
    EXPECT_LE(measured.after.fill_area + measured.after.cut_area, given.after.fill_area + given.after.cut_area);
  }
}

TEST_F(TerrainDomainTest, HullBridgesTheHoles) {
  TerrainReport report;
  const Raster dod = Analyse(DomainKind::kHull, &report);
  for (const auto& [c, r] : std::vector<std::pair<int, int>>{{5, 5}, {31, 20}, {26, 41}}) {
    EXPECT_FALSE(std::isnan(dod.values[r * kColumns + c])) << c << ", " << r;
  }
  EXPECT_GT(report.after.overlap_area, Cellwise(holes_).area + 100 * kDx * kDy);
}

}  // namespace
}  // namespace surfreg

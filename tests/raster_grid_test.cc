// A raster keeps its grid (issue 26): DEMs read from GeoTIFFs are meshed on
// their own cells, split by one diagonal rule, in any CRS. So a uniform
// change over a block of nodes has the volume of those nodes' cells, and
// two DEMs of the same ground on the same grid agree between the nodes, also
// after lon/lat is turned into metres (where a Delaunay triangulation picks
// each cell's diagonal from rounding noise, differently in each DEM).
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "measure/measures.h"
#include "registration/align.h"
#include "tests/testing/file_checks.h"
#include "tools/align_config.h"
#include "terrain/geo_frame.h"
#include "io/raster_io.h"
#include "terrain/terrain.h"

namespace surfreg {
namespace {

// Rough ground: heights from a hash of the global cell index, multiples of
// 1/64 (exact in Float32) between 100 and 120 m, so the diagonal chosen in
// a cell changes the surface a lot.
double Ground(int column, int row) {
  uint64_t x = static_cast<uint64_t>(column) * 0x9e3779b97f4a7c15ULL ^
               static_cast<uint64_t>(row) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 31)) * 0x94d049bb133111ebULL;
  x ^= x >> 29;
  return 100.0 + static_cast<double>(x % 1280) / 64.0;
}

struct Block {  // nodes [column, column + columns) x [row, row + rows), and single nodes
  int column = 0, row = 0, columns = 0, rows = 0;
  std::vector<std::pair<int, int>> singles;
  bool Has(int c, int r) const {
    for (const auto& [sc, sr] : singles) {
      if (sc == c && sr == r) return true;
    }
    return c >= column && c < column + columns && r >= row && r < row + rows;
  }
  int nodes() const { return columns * rows + static_cast<int>(singles.size()); }
};

// A `columns` x `rows` window of the global grid starting at global cell
// (first_column, first_row), the block lowered by `drop`. The geotransform
// is the window's own (its corner computed from the global one, as GDAL
// does for a window), so two windows place the same node differently by
// rounding.
Raster Dem(const std::array<double, 6>& global, const std::string& crs, int first_column,
           int first_row, int columns, int rows, const Block& block, double drop) {
  Raster r;
  r.columns = columns;
  r.rows = rows;
  r.geotransform = global;
  r.geotransform[0] += first_column * global[1];
  r.geotransform[3] += first_row * global[5];
  r.crs_wkt = crs.empty() ? "" : ParseCrs(crs, "test").wkt;
  for (int row = 0; row < rows; ++row) {
    for (int c = 0; c < columns; ++c) {
      const int gc = first_column + c, gr = first_row + row;
      r.values.push_back(Ground(gc, gr) - (block.Has(gc, gr) ? drop : 0.0));
    }
  }
  return r;
}

class RasterGridTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const Raster& raster) {
    const std::string path = dir_.path() + "/" + name;
    WriteGeoTiff(path, raster, name);
    return path;
  }
  TerrainInputs Read(const std::string& reference, const std::string& moving) {
    config_.reference = reference;
    config_.moving = moving;
    return ReadTerrainInputs(config_);
  }

  testing::TempDir dir_;
  AlignConfig config_;
};

// --- a projected grid --------------------------------------------------------

// (A north-up grid in its own CRS has columns of equal x and rows of equal
// y, so every cell is an exact rectangle and a Delaunay triangulation's
// tie-breaking happened to split them all alike too; the turned and lon/lat
// grids below are where it did not.)
TEST_F(RasterGridTest, BlockChangeOnAProjectedGridIsEightTimesItsCells) {
  // 0.3 m cells at UTM-sized coordinates: cell centres rounded.
  const double h = 0.3;
  const std::array<double, 6> gt = {431234.5, h, 0.0, 6123456.7, 0.0, -h};
  const int columns = 40, rows = 30;
  const Block block{11, 7, 9, 6, {}};
  const std::string a = Write("a.tif", Dem(gt, "EPSG:32760", 0, 0, columns, rows, block, 0.0));
  const std::string b = Write("b.tif", Dem(gt, "EPSG:32760", 0, 0, columns, rows, block, 8.0));
  config_.terrain.dod = dir_.path() + "/dod.tif";
  const TerrainInputs inputs = Read(a, b);
  AlignResult identity;
  identity.matrix.setIdentity();
  const TerrainReport report = AnalyseTerrain(config_, inputs, identity);
  WriteTerrainOutputs(config_, inputs, report);

  const MeasureSummary& s = report.after;
  const double cut = 8.0 * h * h * block.nodes();
  std::printf("projected block: cut %.12g, 8 h^2 N %.12g (relative %.2e), fill %.3g\n",
              s.volume_below, cut, s.volume_below / cut - 1, s.volume_above);
  EXPECT_NEAR(s.volume_below, cut, 1e-9 * cut);
  EXPECT_NEAR(s.cut_detected, cut, 1e-9 * cut);
  EXPECT_LE(s.volume_above, 1e-12 * cut);  // no fill: rounding only
  EXPECT_LE(s.fill_detected, 1e-12 * cut);
  EXPECT_NEAR(s.overlap_area, (columns - 1) * (rows - 1) * h * h, 1e-9 * s.overlap_area);

  // The DoD is the cellwise difference of the two rasters.
  const Raster ra = ReadRaster(a), rb = ReadRaster(b), dod = ReadRaster(config_.terrain.dod);
  ASSERT_EQ(dod.values.size(), ra.values.size());
  for (std::size_t k = 0; k < dod.values.size(); ++k) {
    EXPECT_EQ(dod.values[k], static_cast<float>(rb.values[k] - ra.values[k])) << k;
  }
}

// Single nodes: each one's hat function covers one cell only with six
// triangles around it, which a Delaunay triangulation gives by chance.
TEST_F(RasterGridTest, ChangeAtSingleNodesIsOneCellEach) {
  const double h = 0.3;
  const std::array<double, 6> gt = {431234.5, h, 0.0, 6123456.7, 0.0, -h};
  Block singles;
  for (int k = 0; k < 12; ++k) singles.singles.push_back({3 + 3 * k, 2 + (7 * k) % 25});
  const std::string a = Write("a.tif", Dem(gt, "EPSG:32760", 0, 0, 40, 30, singles, 0.0));
  const std::string b = Write("b.tif", Dem(gt, "EPSG:32760", 0, 0, 40, 30, singles, 8.0));
  const TerrainInputs inputs = Read(a, b);
  const MeasureSummary s = Measure(inputs.reference, inputs.moving);
  const double cut = 8.0 * h * h * singles.nodes();
  std::printf("single nodes: cut %.12g, 8 h^2 N %.12g (relative %.2e)\n", s.volume_below, cut,
              s.volume_below / cut - 1);
  EXPECT_NEAR(s.volume_below, cut, 1e-9 * cut);
  EXPECT_LE(s.volume_above, 1e-12 * cut);
}

// A rigid motion moves the points, not the cells. Turned 20° about z (no
// longer rows of equal y: Delaunay would pick each diagonal from rounding),
// the block's cut is still 8 h² N, and two windows of one DEM, both turned,
// still agree between the nodes.
TEST_F(RasterGridTest, RigidlyMovedGridsKeepTheirCells) {
  const double h = 0.3;
  const std::array<double, 6> gt = {431234.5, h, 0.0, 6123456.7, 0.0, -h};
  Eigen::Matrix4d turn = Eigen::Matrix4d::Identity();
  turn.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.349, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  turn.topRightCorner<3, 1>() = Eigen::Vector3d(-1000.0, 2000.0, 3.0);
  const Block block{11, 7, 9, 6, {{30, 20}, {34, 4}, {3, 25}}};
  const TerrainInputs change =
      Read(Write("a.tif", Dem(gt, "EPSG:32760", 0, 0, 40, 30, block, 0.0)),
           Write("b.tif", Dem(gt, "EPSG:32760", 0, 0, 40, 30, block, 8.0)));
  const MeasureSummary s =
      Measure(TransformSurface(change.reference, turn), TransformSurface(change.moving, turn));
  const double cut = 8.0 * h * h * block.nodes();
  std::printf("turned block: cut %.12g, 8 h^2 N %.12g (relative %.2e)\n", s.volume_below, cut,
              s.volume_below / cut - 1);
  EXPECT_NEAR(s.volume_below, cut, 1e-9 * cut);
  EXPECT_LE(s.volume_above, 1e-12 * cut);

  const Block none;
  const TerrainInputs windows =
      Read(Write("c.tif", Dem(gt, "EPSG:32760", 0, 0, 40, 30, none, 0.0)),
           Write("d.tif", Dem(gt, "EPSG:32760", 7, 5, 40, 30, none, 0.0)));
  const MeasureSummary w =
      Measure(TransformSurface(windows.reference, turn), TransformSurface(windows.moving, turn));
  std::printf("turned windows: mean |dz| %.3g m\n", w.mean_abs_dz);
  EXPECT_GT(w.overlap_area, 0.5 * w.domain_area_a);
  EXPECT_LT(w.mean_abs_dz, 1e-6);
}

// --- a grid regular in lon/lat ----------------------------------------------

// Area in UTM zone 60S (EPSG:32760, by PROJ) of the lon/lat cell centred at
// `centre` with sides `h` degrees: what a node's hat function covers on a
// fine, smooth grid.
double UtmCellArea(const Point2& centre, double h) {
  OGRSpatialReference from, to;
  from.SetFromUserInput("EPSG:4326");
  to.SetFromUserInput("EPSG:32760");
  from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&from, &to));
  double x[4] = {centre.x - h / 2, centre.x + h / 2, centre.x + h / 2, centre.x - h / 2};
  double y[4] = {centre.y - h / 2, centre.y - h / 2, centre.y + h / 2, centre.y + h / 2};
  EXPECT_TRUE(t && t->Transform(4, x, y));
  double twice = 0;
  for (int i = 0; i < 4; ++i) twice += x[i] * y[(i + 1) % 4] - x[(i + 1) % 4] * y[i];
  return 0.5 * std::fabs(twice);
}

constexpr double kDegree = 0.0001;  // about 9 m east, 11 m north at 36.9 S
const std::array<double, 6> kLonLat = {174.7512, kDegree, 0.0, -36.8631, 0.0, -kDegree};

TEST_F(RasterGridTest, BlockChangeOnALonLatGridIsEightTimesItsMetricCells) {
  const int columns = 40, rows = 30;
  const Block block{12, 9, 10, 7, {}};
  const Raster before = Dem(kLonLat, "EPSG:4326", 0, 0, columns, rows, block, 0.0);
  const std::string a = Write("a.tif", before);
  const std::string b = Write("b.tif", Dem(kLonLat, "EPSG:4326", 0, 0, columns, rows, block, 8.0));
  const TerrainInputs inputs = Read(a, b);
  ASSERT_EQ(inputs.frame.Describe(), "UTM zone 60S (WGS 84; EPSG:32760)");
  double cells = 0;
  for (int r = block.row; r < block.row + block.rows; ++r) {
    for (int c = block.column; c < block.column + block.columns; ++c) {
      cells += UtmCellArea(before.CellCentre(c, r), kDegree);
    }
  }
  const MeasureSummary s = Measure(inputs.reference, inputs.moving);
  std::printf("lon/lat block: cut %.12g, 8 m x cells %.12g (relative %.2e), fill %.3g\n",
              s.volume_below, 8.0 * cells, s.volume_below / (8.0 * cells) - 1, s.volume_above);
  EXPECT_LE(s.volume_above, 1e-12 * s.volume_below);  // no fill: rounding only
  EXPECT_NEAR(s.volume_below, 8.0 * cells, 1e-3 * 8.0 * cells);
}

TEST_F(RasterGridTest, TwoLonLatWindowsOfOneDemAgreeBetweenTheNodes) {
  // The same ground, two overlapping windows (their corners differ, so the
  // same node's lon/lat differs by rounding): zero volume to rounding.
  const Block none;
  const std::string a = Write("a.tif", Dem(kLonLat, "EPSG:4326", 0, 0, 40, 30, none, 0.0));
  const std::string b = Write("b.tif", Dem(kLonLat, "EPSG:4326", 7, 5, 40, 30, none, 0.0));
  const TerrainInputs inputs = Read(a, b);
  ASSERT_EQ(inputs.frame.Describe(), "UTM zone 60S (WGS 84; EPSG:32760)");
  const MeasureSummary s = Measure(inputs.reference, inputs.moving);
  std::printf("two windows: rho_d %.3g m^3 over %.6g m^2, mean |dz| %.3g m, rho'_d %.3g m\n",
              s.rho_d, s.overlap_area, s.mean_abs_dz, s.rho_d_axial);
  EXPECT_GT(s.overlap_area, 0.5 * s.domain_area_a);
  // Node positions differ by ~1e-9 m, the slopes are ~1: a micrometre is
  // far above rounding, and far below what a different diagonal makes.
  EXPECT_LT(s.mean_abs_dz, 1e-6) << "rho_d " << s.rho_d << " over " << s.overlap_area;
  EXPECT_LT(s.rho_d_axial, 1e-6);
}

}  // namespace
}  // namespace surfreg

namespace surfreg {
namespace {

// Issue 26's case: two lon/lat DEMs of the same smooth ground, the moving one
// misplaced by one cell west and 3 m up. Aligned, they show no change: the
// cells of both are split alike, so the surfaces agree between the nodes
// too (with Delaunay diagonals the same test reported a mean |dz| of 1.1 m
// on a real pair).
TEST_F(RasterGridTest, AlignedLonLatDemsOffsetByOneCellShowNoChange) {
  const int columns = 60, rows = 50;
  // Heights in multiples of 1/64 m (exact in Float32), smooth in the global
  // cell index so that a one-cell offset is in the basin of the solver.
  auto ground = [](int c, int r) {
    const double z = 100.0 + 15.0 * std::sin(c / 9.0) * std::cos(r / 7.0) + 0.2 * c - 0.1 * r;
    return std::round(z * 64.0) / 64.0;
  };
  auto dem = [&](int shift, double lift) {
    Raster r;
    r.columns = columns;
    r.rows = rows;
    r.geotransform = kLonLat;
    r.crs_wkt = ParseCrs("EPSG:4326", "test").wkt;
    for (int row = 0; row < rows; ++row) {
      for (int c = 0; c < columns; ++c) r.values.push_back(ground(c + shift, row) + lift);
    }
    return r;
  };
  // The moving DEM's value at column c is the ground at c + 1: placed one cell west.
  const TerrainInputs inputs = Read(Write("a.tif", dem(0, 0.0)), Write("b.tif", dem(1, 3.0)));
  const AlignResult result = Align(inputs.reference, inputs.moving, config_.options);
  ASSERT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  const TerrainReport report = AnalyseTerrain(config_, inputs, result);
  const MeasureSummary& s = report.after;
  const double per_area = (s.volume_above + s.volume_below) / s.overlap_area;
  std::printf("aligned lon/lat DEMs one cell apart: (fill + cut) / overlap area %.3g m "
              "(fill %.3g, cut %.3g m^3 over %.6g m^2); before %.3g m\n",
              per_area, s.volume_above, s.volume_below, s.overlap_area,
              (report.before.volume_above + report.before.volume_below) / report.before.overlap_area);
  EXPECT_GT(s.overlap_area, 0.8 * s.domain_area_a);
  EXPECT_LT(per_area, 1e-3);
}

}  // namespace
}  // namespace surfreg

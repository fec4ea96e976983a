// A raster's cells as samples (RasterToSurface, GridCellsToSurface,
// RasterBlockToSurface) and a surface moved by a matrix (TransformSurface),
// made by chunks of rows or samples on any number of threads: checked bit
// for bit against one plain pass written here (each cell centre as
// Raster::CellCentre, then MakeSurface), on inputs of several chunks.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "io/raster_io.h"
#include "measure/surface.h"
#include "registration/align.h"
#include "terrain/tiled_measure.h"
#include "tests/testing/file_checks.h"

namespace surfreg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 300 × 700 cells (three bands of rows of 2^16 cells), some not finite: a
// scattered tenth, one whole row, a block, an infinity.
Raster TestRaster(const std::array<double, 6>& gt) {
  Raster r;
  r.columns = 300, r.rows = 700;
  r.geotransform = gt;
  r.source = "test.tif";
  r.values.resize(static_cast<std::size_t>(r.columns) * r.rows);
  uint64_t state = 12345;
  for (int row = 0; row < r.rows; ++row) {
    for (int column = 0; column < r.columns; ++column) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      double z = 250.0 + 30.0 * std::sin(column / 23.0) * std::cos(row / 41.0) + (state >> 40) * 1e-7;
      if ((state >> 33) % 10 == 0 || row == 300 || (row >= 500 && row < 520 && column < 100)) z = kNaN;
      r.values[static_cast<std::size_t>(row) * r.columns + column] = z;
    }
  }
  r.values[1234] = std::numeric_limits<double>::infinity();
  return r;
}

// One plain pass: the valid cells' centres and heights in row-major order.
Surface OnePass(const Raster& r, double origin_step, std::vector<int64_t>* cell_of_sample) {
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  cell_of_sample->clear();
  for (int row = 0; row < r.rows; ++row) {
    for (int column = 0; column < r.columns; ++column) {
      const int64_t cell = static_cast<int64_t>(row) * r.columns + column;
      const double z = r.values[static_cast<std::size_t>(cell)];
      if (!std::isfinite(z)) continue;
      const Point2 p = r.CellCentre(column, row);
      points.push_back({p.x, p.y, z});
      cells.push_back({column, row});
      cell_of_sample->push_back(cell);
    }
  }
  Surface s = MakeSurface(points, {}, r.source, origin_step);
  s.raster_cell = cells;
  return s;
}

void ExpectSameSamples(const Surface& expected, const Surface& actual, const std::string& label) {
  EXPECT_EQ(actual.origin, expected.origin) << label;
  ASSERT_EQ(actual.size(), expected.size()) << label;
  ASSERT_EQ(actual.raster_cell.size(), expected.raster_cell.size()) << label;
  int64_t different = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    // Bit for bit: == on doubles, no tolerance.
    if (actual.xy[i].x != expected.xy[i].x || actual.xy[i].y != expected.xy[i].y ||
        actual.z[i] != expected.z[i]) {
      ++different;
    }
    if (!expected.raster_cell.empty() && (actual.raster_cell[i].column != expected.raster_cell[i].column ||
                                          actual.raster_cell[i].row != expected.raster_cell[i].row)) {
      ++different;
    }
  }
  EXPECT_EQ(different, 0) << label;
  EXPECT_EQ(actual.weight, expected.weight) << label;
  EXPECT_EQ(actual.source, expected.source) << label;
}

TEST(RasterSamples, ByChunksEqualOnePassOnAnyThreadCount) {
  // North-up UTM-sized, and sheared (a raster made in memory may be).
  for (const std::array<double, 6>& gt : {std::array<double, 6>{500123.25, 10.0, 0.0, 4000456.75, 0.0, -10.0},
                                          std::array<double, 6>{1000.5, 2.0, 0.3, 7000.25, -0.2, -2.5}}) {
    const Raster r = TestRaster(gt);
    for (const double step : {1.0, 0.5, 0.0}) {
      std::vector<int64_t> expected_cells;
      const Surface expected = OnePass(r, step, &expected_cells);
      ASSERT_GT(expected.size(), 150000u);
      for (const int threads : {1, 2, 8}) {
        std::vector<int64_t> cells = {7, 7, 7};  // replaced, not appended to
        const Surface s = RasterToSurface(r, &cells, step, threads);
        const std::string label = "gt[2] " + std::to_string(gt[2]) + ", step " + std::to_string(step) +
                                  ", threads " + std::to_string(threads);
        ExpectSameSamples(expected, s, label);
        EXPECT_EQ(cells, expected_cells) << label;
      }
    }
  }
}

TEST(RasterSamples, WindowAboutAGivenOrigin) {
  const Raster whole = TestRaster({500123.25, 10.0, 0.0, 4000456.75, 0.0, -10.0});
  // A window of 250 × 600 cells at column 20, row 60, as a tiled measure reads it.
  const SampleWindow w{20, 60, 250, 600};
  std::vector<double> values;
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  for (int row = w.row; row < w.row + w.rows; ++row) {
    for (int column = w.column; column < w.column + w.columns; ++column) {
      const double z = whole.values[static_cast<std::size_t>(row) * whole.columns + column];
      values.push_back(z);
      if (!std::isfinite(z)) continue;
      const Point2 p = whole.CellCentre(column, row);
      points.push_back({p.x, p.y, z});
      cells.push_back({column, row});
    }
  }
  const std::array<double, 3> origin = {501000.0, 3999000.0, 0.0};
  Surface expected;
  expected.origin = origin;
  expected.source = "block";
  for (const auto& p : points) {
    expected.xy.push_back({p[0] - origin[0], p[1] - origin[1]});
    expected.z.push_back(p[2] - origin[2]);
  }
  expected.raster_cell = cells;
  for (const int threads : {1, 2, 8}) {
    ExpectSameSamples(expected,
                      RasterBlockToSurface(whole.geotransform, w, values.data(), values.size(), origin, "block",
                                           threads),
                      "threads " + std::to_string(threads));
  }
  EXPECT_TRUE(testing::Contains(
      testing::ErrorOf([&] { RasterBlockToSurface(whole.geotransform, w, values.data(), 10, origin, "block"); }),
      "block: 10 values for a window of 250 x 600"));
}

TEST(RasterSamples, EveryCellNodataOrTooFewValuesIsAnError) {
  Raster r;
  r.columns = 400, r.rows = 400;
  r.source = "empty.tif";
  r.values.assign(160000, kNaN);
  EXPECT_EQ(testing::ErrorOf([&] { RasterToSurface(r, nullptr, 1.0, 2); }), "empty.tif: every cell is nodata");
  r.values.resize(1000, 1.0);
  EXPECT_EQ(testing::ErrorOf([&] { RasterToSurface(r, nullptr, 1.0, 2); }),
            "empty.tif: 1000 values for 400 x 400 cells");
}

TEST(TransformSurfaceTest, ByChunksEqualsOnePassOnAnyThreadCount) {
  const Raster r = TestRaster({500123.25, 10.0, 0.0, 4000456.75, 0.0, -10.0});
  Surface surface = RasterToSurface(r, nullptr);
  surface.weight.resize(surface.size());
  for (std::size_t i = 0; i < surface.size(); ++i) surface.weight[i] = 1.0 + static_cast<double>(i % 7);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, -0.5, 1.0).normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(-123.5, 77.25, 3.5);
  // One pass: each sample rotated about the origin, the origin moved apart.
  const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
  const Eigen::Vector3d moved_origin =
      rotation * Eigen::Vector3d(surface.origin[0], surface.origin[1], surface.origin[2]) +
      m.topRightCorner<3, 1>();
  std::vector<std::array<double, 3>> points(surface.size());
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const Eigen::Vector3d p = rotation * Eigen::Vector3d(surface.xy[i].x, surface.xy[i].y, surface.z[i]);
    points[i] = {p.x() + moved_origin.x(), p.y() + moved_origin.y(), p.z() + moved_origin.z()};
  }
  Surface expected = MakeSurface(points, surface.weight, surface.source);
  expected.raster_cell = surface.raster_cell;
  for (const int threads : {1, 2, 8}) {
    ExpectSameSamples(expected, TransformSurface(surface, m, threads), "threads " + std::to_string(threads));
  }
}

}  // namespace
}  // namespace surfreg

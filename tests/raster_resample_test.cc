// A surface resampled onto a raster grid (io/raster_resample.h): a planar
// DEM moved rigidly is still a plane, so every cell inside the moved
// footprint must hold that plane's height at its centre, and the cells
// outside it nodata; the heights are the same bits on any number of threads.
#include "io/raster_resample.h"

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "io/raster_io.h"

namespace surfreg {
namespace {

constexpr int kColumns = 320, kRows = 300;  // 96,000 cells: more than one chunk
constexpr double kCell = 2.0, kX0 = 1000.0, kY0 = 5000.0;

double PlaneHeight(double x, double y) { return 3.0 + 0.2 * (x - kX0) - 0.1 * (y - kY0); }

Raster PlaneRaster() {
  Raster r;
  r.columns = kColumns;
  r.rows = kRows;
  r.geotransform = {kX0, kCell, 0.0, kY0, 0.0, -kCell};
  r.source = "plane";
  r.values.resize(static_cast<std::size_t>(kColumns) * kRows);
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      const Point2 c = r.CellCentre(column, row);
      r.values[static_cast<std::size_t>(row) * kColumns + column] = PlaneHeight(c.x, c.y);
    }
  }
  return r;
}

// The raster's samples moved by `rotation` about `centre`, then by `shift`.
Surface Moved(const Surface& s, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& centre,
              const Eigen::Vector3d& shift) {
  std::vector<std::array<double, 3>> points(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d p(s.xy[i].x + s.origin[0], s.xy[i].y + s.origin[1], s.z[i] + s.origin[2]);
    const Eigen::Vector3d q = rotation * (p - centre) + centre + shift;
    points[i] = {q.x(), q.y(), q.z()};
  }
  Surface moved = MakeSurface(points, {}, "moved");
  moved.raster_cell = s.raster_cell;
  return moved;
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(ResampleOntoGrid, MovedPlaneHasThePlanesHeightsInsideItsFootprintAndNodataOutside) {
  const Raster grid = PlaneRaster();
  const Surface surface = RasterToSurface(grid, nullptr);
  const double angle = 0.3 * M_PI / 180;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d centre(kX0 + 320, kY0 - 300, 0), shift(31.3, -27.1, 0.5);
  const Surface moved = Moved(surface, rotation, centre, shift);
  const Raster out = ResampleOntoGrid(moved, grid, Execution{1});
  ASSERT_EQ(out.columns, kColumns);
  ASSERT_EQ(out.rows, kRows);
  int inside = 0, outside = 0;
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      const Point2 c = out.CellCentre(column, row);
      const double value = out.values[static_cast<std::size_t>(row) * kColumns + column];
      // Where the cell's centre came from: the motion undone in xy.
      const Eigen::Vector3d from = rotation.transpose() * (Eigen::Vector3d(c.x, c.y, 0) - centre - shift) + centre;
      const double u = (from.x() - kX0) / kCell, v = (kY0 - from.y()) / kCell;  // in cells
      // How far inside the hull of the cells' centres (in cells).
      const double margin = std::min({u - 0.5, kColumns - 0.5 - u, v - 0.5, kRows - 0.5 - v});
      if (margin > 0.01) {
        ++inside;
        ASSERT_TRUE(std::isfinite(value)) << column << "," << row;
        // The moved plane at (x, y): the original plane's height at `from`, moved up by the shift.
        EXPECT_NEAR(value, PlaneHeight(from.x(), from.y()) + shift.z(), 1e-9) << column << "," << row;
      } else if (margin < -0.01) {
        ++outside;
        EXPECT_TRUE(std::isnan(value)) << column << "," << row;
      }
    }
  }
  EXPECT_GT(inside, 80000);
  EXPECT_GT(outside, 3000);
}

TEST(ResampleOntoGrid, IsTheSameOnOneTwoAndEightThreads) {
  const Raster grid = PlaneRaster();
  const Surface surface = RasterToSurface(grid, nullptr);
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.4 * M_PI / 180, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(0.2 * M_PI / 180, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Surface moved = Moved(surface, rotation, Eigen::Vector3d(kX0 + 320, kY0 - 300, 100), {5.3, 7.9, -1.0});
  const Raster one = ResampleOntoGrid(moved, grid, Execution{1});
  for (const int threads : {2, 8}) {
    EXPECT_TRUE(SameBits(ResampleOntoGrid(moved, grid, Execution{threads}).values, one.values)) << threads;
  }
  // A grid in other coordinates (here the surface's less a constant), its
  // cells' centres mapped into the surface's: the same heights.
  Raster local = grid;
  local.geotransform[0] -= kX0;
  local.geotransform[3] -= kY0;
  const GridToSurface to_surface = [](std::vector<std::array<double, 3>>* points) {
    for (auto& p : *points) p[0] += kX0, p[1] += kY0;
  };
  const Raster mapped = ResampleOntoGrid(moved, local, to_surface, Execution{1});
  ASSERT_EQ(mapped.values.size(), one.values.size());
  for (std::size_t i = 0; i < one.values.size(); ++i) {
    ASSERT_EQ(std::isnan(mapped.values[i]), std::isnan(one.values[i])) << i;
    if (!std::isnan(one.values[i])) {
      EXPECT_NEAR(mapped.values[i], one.values[i], 1e-9) << i;
    }
  }
  EXPECT_TRUE(SameBits(ResampleOntoGrid(moved, local, to_surface, Execution{8}).values, mapped.values));
}

}  // namespace
}  // namespace surfreg

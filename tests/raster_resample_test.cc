// A surface resampled onto a raster grid (io/raster_resample.h): a planar
// DEM moved rigidly is still a plane, so every cell inside the moved
// footprint must hold that plane's height at its centre, and the cells
// outside it nodata; the heights are the same bits on any number of threads.
#include "io/raster_resample.h"

#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "io/raster_io.h"
#include "measure/predicates.h"

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

bool SameBits(const UninitializedVector<double>& a, const UninitializedVector<double>& b) {
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

// A small bumpy raster with nodata holes (and an isolated valid sample).
Raster BumpyRaster() {
  Raster r;
  r.columns = 24;
  r.rows = 20;
  r.geotransform = {kX0, kCell, 0.0, kY0, 0.0, -kCell};
  r.source = "bumpy";
  std::mt19937 random(7);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  r.values.resize(static_cast<std::size_t>(r.columns) * r.rows);
  for (int row = 0; row < r.rows; ++row) {
    for (int column = 0; column < r.columns; ++column) {
      const bool hole = (row >= 6 && row <= 8 && column >= 9 && column <= 12) || (row == 14 && column == 4) ||
                        (row == 2 && (column == 17 || column == 19)) || (row == 3 && column == 18) ||
                        (row == 1 && column == 18);
      r.values[static_cast<std::size_t>(row) * r.columns + column] =
          hole ? std::nan("") : 100 + 5 * std::sin(column / 3.0) * std::cos(row / 4.0) + noise(random);
    }
  }
  return r;
}

// By brute force: every rule triangle of every complete cell (grid_mesh.h)
// tested against every cell centre of the grid, exactly; the height by
// barycentric coordinates; NaN where no triangle holds the centre.
std::vector<double> BruteForce(const Raster& source, const Surface& moved, const Raster& grid) {
  // The moved samples by (column, row).
  std::vector<int> sample(static_cast<std::size_t>(source.columns) * source.rows, -1);
  for (std::size_t i = 0; i < moved.raster_cell.size(); ++i) {
    sample[static_cast<std::size_t>(moved.raster_cell[i].row) * source.columns + moved.raster_cell[i].column] =
        static_cast<int>(i);
  }
  std::vector<std::array<int, 3>> triangles;
  for (int r = 0; r + 1 < source.rows; ++r) {
    for (int c = 0; c + 1 < source.columns; ++c) {
      const int k00 = sample[r * source.columns + c], k10 = sample[r * source.columns + c + 1];
      const int k01 = sample[(r + 1) * source.columns + c], k11 = sample[(r + 1) * source.columns + c + 1];
      if (k00 < 0 || k10 < 0 || k01 < 0 || k11 < 0) continue;
      triangles.push_back({k00, k10, k11});
      triangles.push_back({k00, k11, k01});
    }
  }
  std::vector<double> out(static_cast<std::size_t>(grid.columns) * grid.rows, std::nan(""));
  for (int row = 0; row < grid.rows; ++row) {
    for (int column = 0; column < grid.columns; ++column) {
      const Point2 centre = grid.CellCentre(column, row);
      const Point2 p{centre.x - moved.origin[0], centre.y - moved.origin[1]};
      for (const auto& t : triangles) {
        const Point2 &a = moved.xy[t[0]], &b = moved.xy[t[1]], &c = moved.xy[t[2]];
        const double sign = Orient2D(a, b, c) > 0 ? 1.0 : -1.0;
        const double w[3] = {Orient2D(b, c, p) * sign, Orient2D(c, a, p) * sign, Orient2D(a, b, p) * sign};
        if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
        const double sum = w[0] + w[1] + w[2];
        out[static_cast<std::size_t>(row) * grid.columns + column] =
            (w[0] * moved.z[t[0]] + w[1] * moved.z[t[1]] + w[2] * moved.z[t[2]]) / sum + moved.origin[2];
        break;
      }
    }
  }
  return out;
}

// Equal NaN sets and heights within 1e-9; the number of heights found.
int ExpectSameHeights(const std::vector<double>& expected, const UninitializedVector<double>& actual,
                      const std::string& label) {
  EXPECT_EQ(expected.size(), actual.size()) << label;
  int found = 0;
  for (std::size_t i = 0; i < expected.size() && i < actual.size(); ++i) {
    EXPECT_EQ(std::isnan(expected[i]), std::isnan(actual[i])) << label << " cell " << i;
    if (std::isnan(expected[i]) || std::isnan(actual[i])) continue;
    EXPECT_NEAR(actual[i], expected[i], 1e-9) << label << " cell " << i;
    ++found;
  }
  return found;
}

TEST(ResampleOntoGrid, MovedRasterWithHolesMatchesBruteForceOnItsOwnAndOtherGrids) {
  const Raster source = BumpyRaster();
  const Surface surface = RasterToSurface(source, nullptr);
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(17 * M_PI / 180, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(1.0 * M_PI / 180, Eigen::Vector3d::UnitY()))
                                       .toRotationMatrix();
  const Surface moved = Moved(surface, rotation, Eigen::Vector3d(kX0 + 24, kY0 - 20, 100), {3.1, -1.7, 0.4});
  Raster finer = source;  // another spacing and offset
  finer.columns = 40, finer.rows = 37;
  finer.geotransform = {kX0 - 3.3, 1.4, 0.0, kY0 + 4.1, 0.0, -1.4};
  Raster upward = source;  // rows going up (a mirrored geotransform)
  upward.geotransform = {kX0 - 2.0, kCell, 0.0, kY0 - 42.0, 0.0, kCell};
  for (const Raster* grid : {&source, static_cast<const Raster*>(&finer), static_cast<const Raster*>(&upward)}) {
    const std::vector<double> expected = BruteForce(source, moved, *grid);
    for (const int threads : {1, 3}) {
      const Raster out = ResampleOntoGrid(moved, *grid, Execution{threads});
      const int found = ExpectSameHeights(expected, out.values, "grid " + std::to_string(grid->columns));
      EXPECT_GT(found, grid->columns * grid->rows / 3);
    }
  }
}

TEST(ResampleOntoGrid, AGridFarLargerThanTheRasterOrBesideItGetsNodataAroundIt) {
  const Raster source = BumpyRaster();
  const Surface surface = RasterToSurface(source, nullptr);
  Raster large = source;  // the raster in a corner of a grid 40 times its size
  large.columns = 24 * 8, large.rows = 20 * 5;
  large.geotransform[0] -= 10 * kCell, large.geotransform[3] += 7 * kCell;
  const std::vector<double> expected = BruteForce(source, surface, large);
  EXPECT_GT(ExpectSameHeights(expected, ResampleOntoGrid(surface, large, Execution{2}).values, "large"), 400);
  Raster beside = source;  // no cell under the raster
  beside.geotransform[0] += 100 * kCell;
  for (const double value : ResampleOntoGrid(surface, beside, Execution{2}).values) EXPECT_TRUE(std::isnan(value));
}

TEST(ResampleOntoGrid, ARasterOntoItsOwnGridUnmovedKeepsItsHeightsAndDropsCellsOutsideCompleteOnes) {
  const Raster source = BumpyRaster();
  const Surface surface = RasterToSurface(source, nullptr);
  const Raster out = ResampleOntoGrid(surface, source, Execution{2});
  const std::vector<double> expected = BruteForce(source, surface, source);
  ExpectSameHeights(expected, out.values, "unmoved");
  int kept = 0;
  for (std::size_t i = 0; i < out.values.size(); ++i) {
    if (std::isnan(out.values[i])) continue;
    ++kept;
    EXPECT_EQ(out.values[i], source.values[i]) << i;  // a centre at a sample: its height, to the bit
  }
  // Kept: the samples that are a corner of a complete cell; so not the
  // isolated one at column 18, row 2.
  const auto valid = [&](int c, int r) {
    return c >= 0 && r >= 0 && c < source.columns && r < source.rows &&
           !std::isnan(source.values[static_cast<std::size_t>(r) * source.columns + c]);
  };
  int corners = 0;
  for (int r = 0; r < source.rows; ++r) {
    for (int c = 0; c < source.columns; ++c) {
      bool corner = false;
      for (int dr = -1; dr <= 0; ++dr) {
        for (int dc = -1; dc <= 0; ++dc) {
          corner |= valid(c + dc, r + dr) && valid(c + dc + 1, r + dr) && valid(c + dc, r + dr + 1) &&
                    valid(c + dc + 1, r + dr + 1);
        }
      }
      corners += corner;
    }
  }
  EXPECT_TRUE(std::isnan(out.values[2 * 24 + 18]));
  EXPECT_EQ(kept, corners);
  EXPECT_GT(kept, 24 * 20 - 25);
}

TEST(ResampleOntoGrid, AFoldedRasterStillGetsItsHeightsAwayFromTheFold) {
  const Raster grid = PlaneRaster();
  Surface surface = RasterToSurface(grid, nullptr);
  // One sample pushed across its neighbour: its cells fold over (the
  // general path, which leaves them and those around them out).
  const std::size_t folded = 150 * kColumns + 160;
  surface.xy[folded].x += 2.5 * kCell;
  const Raster out = ResampleOntoGrid(surface, grid, Execution{2});
  int checked = 0;
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      if (std::abs(row - 150) <= 4 && std::abs(column - 160) <= 5) continue;
      if (row == 0 || column == 0 || row == kRows - 1 || column == kColumns - 1) continue;
      const Point2 c = out.CellCentre(column, row);
      ASSERT_NEAR(out.values[static_cast<std::size_t>(row) * kColumns + column], PlaneHeight(c.x, c.y), 1e-9)
          << column << "," << row;
      ++checked;
    }
  }
  EXPECT_GT(checked, 90000);
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

// The mesh of raster samples (measure/grid_mesh.h): the one diagonal rule,
// in any orientation, on lattices whose Delaunay triangulation is all ties,
// and folded cells left out with the cells around them.
#include "measure/grid_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/input_error.h"
#include "measure/measures.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

using Cell = std::pair<int, int>;  // (column, row)

// A raster's valid samples in row-major order: their cells, and their xy by
// `place` (column, row) -> xy.
struct Samples {
  std::vector<RasterCell> cells;
  std::vector<Point2> xy;
};

Samples Lattice(int columns, int rows, const std::set<Cell>& missing,
                const std::function<Point2(int, int)>& place) {
  Samples s;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      if (missing.count({c, r})) continue;
      s.cells.push_back({c, r});
      s.xy.push_back(place(c, r));
    }
  }
  return s;
}

Point2 NorthUp(int c, int r) { return {100.0 + 2.0 * c, 50.0 - 2.0 * r}; }

// The cells of `triangles` (six indices per cell) as the (column, row) of
// their first corner, checking the rule's corners on the way.
std::vector<Cell> CellsOf(const std::vector<int32_t>& triangles,
                          const std::vector<RasterCell>& cells) {
  std::vector<Cell> out;
  for (std::size_t k = 0; k + 6 <= triangles.size(); k += 6) {
    const RasterCell& p00 = cells[triangles[k]];
    auto at = [&](int i, int dc, int dr) {
      const RasterCell& p = cells[triangles[k + i]];
      return p.column == p00.column + dc && p.row == p00.row + dr;
    };
    EXPECT_TRUE(at(1, 1, 0) && at(2, 1, 1) && at(3, 0, 0) && at(4, 1, 1) && at(5, 0, 1))
        << "cell " << p00.column << ", " << p00.row;
    out.push_back({p00.column, p00.row});
  }
  return out;
}

// A valid triangulation covering the hull: every triangle counter-clockwise
// and the areas adding up to the hull's.
void ExpectValidMesh(const std::vector<Point2>& xy, const Triangulation& mesh) {
  double area = 0;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    ASSERT_GT(Orient2D(xy[v[0]], xy[v[1]], xy[v[2]]), 0.0) << "triangle " << t;
    area += 0.5 * ((xy[v[1]].x - xy[v[0]].x) * (xy[v[2]].y - xy[v[0]].y) -
                   (xy[v[1]].y - xy[v[0]].y) * (xy[v[2]].x - xy[v[0]].x));
  }
  EXPECT_NEAR(area, MeshArea(xy, Triangulate(xy)), 1e-9 * area);
}

// Per kept cell (column, row of its first corner), from the mesh's grid flags.
std::set<Cell> KeptCells(const Samples& s, const Triangulation& mesh,
                         const std::vector<uint8_t>& in_grid) {
  std::set<Cell> kept;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!in_grid[t]) continue;
    int c = INT32_MAX, r = INT32_MAX;
    for (int i = 0; i < 3; ++i) {
      c = std::min(c, s.cells[mesh.triangles[3 * t + i]].column);
      r = std::min(r, s.cells[mesh.triangles[3 * t + i]].row);
    }
    kept.insert({c, r});
  }
  return kept;
}

TEST(GridCellTrianglesTest, EachCellIsSplitFromItsFirstCornerToTheOpposite) {
  const Samples s = Lattice(4, 3, {}, NorthUp);
  const std::vector<int32_t> t = GridCellTriangles(s.cells, "grid");
  // Samples are row-major: (c, r) is index 4 r + c.
  ASSERT_EQ(t.size(), 6u * 3 * 2);
  EXPECT_EQ(std::vector<int32_t>(t.begin(), t.begin() + 6), (std::vector<int32_t>{0, 1, 5, 0, 5, 4}));
  EXPECT_EQ(CellsOf(t, s.cells),
            (std::vector<Cell>{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}}));
}

TEST(GridCellTrianglesTest, OnlyCellsWithFourSamplesInAnyOrder) {
  // (2, 2) missing: its four cells go; (5, 0) missing: two cells at the edge.
  Samples s = Lattice(7, 5, {{2, 2}, {5, 0}}, NorthUp);
  std::set<Cell> expected;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 6; ++c) {
      const bool near_hole = (c == 1 || c == 2) && (r == 1 || r == 2);
      const bool near_edge = (c == 4 || c == 5) && r == 0;
      if (!near_hole && !near_edge) expected.insert({c, r});
    }
  }
  const std::vector<Cell> sorted = CellsOf(GridCellTriangles(s.cells, "grid"), s.cells);
  EXPECT_EQ(std::set<Cell>(sorted.begin(), sorted.end()), expected);
  EXPECT_EQ(sorted.size(), expected.size());
  std::mt19937 rng(3);
  std::shuffle(s.cells.begin(), s.cells.end(), rng);
  const std::vector<Cell> shuffled = CellsOf(GridCellTriangles(s.cells, "grid"), s.cells);
  EXPECT_EQ(std::set<Cell>(shuffled.begin(), shuffled.end()), expected);
  EXPECT_EQ(shuffled.size(), expected.size());
}

TEST(GridCellTrianglesTest, ByChunksOfRowsTheSameAsEveryCellListedOnAnyThreadCount) {
  // 500 × 900 samples (several chunks of rows), a scattered tenth missing,
  // one whole row and a column block too: every complete cell, listed here
  // from a map of the samples, in row-major order, six indices each.
  const int columns = 500, rows = 900;
  std::set<Cell> missing;
  std::mt19937 rng(11);
  for (int k = 0; k < columns * rows / 10; ++k) {
    missing.insert({static_cast<int>(rng() % columns), static_cast<int>(rng() % rows)});
  }
  for (int c = 0; c < columns; ++c) missing.insert({c, 400});
  for (int r = 600; r < 700; ++r) missing.insert({17, r});
  const Samples s = Lattice(columns, rows, missing, NorthUp);
  std::vector<int32_t> index(static_cast<std::size_t>(columns) * rows, -1);
  for (std::size_t i = 0; i < s.cells.size(); ++i) {
    index[static_cast<std::size_t>(s.cells[i].row) * columns + s.cells[i].column] = static_cast<int32_t>(i);
  }
  const auto at = [&](int c, int r) { return index[static_cast<std::size_t>(r) * columns + c]; };
  std::vector<int32_t> expected;
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < columns; ++c) {
      const int32_t p00 = at(c, r), p10 = at(c + 1, r), p01 = at(c, r + 1), p11 = at(c + 1, r + 1);
      if (p00 < 0 || p10 < 0 || p01 < 0 || p11 < 0) continue;
      expected.insert(expected.end(), {p00, p10, p11, p00, p11, p01});
    }
  }
  ASSERT_GT(expected.size(), 6u * 200000);
  for (const int threads : {1, 2, 8}) {
    EXPECT_EQ(GridCellTriangles(s.cells, "grid", Execution{threads}), expected) << threads;
  }
}

TEST(GridCellTrianglesTest, TwoSamplesInOneCellAreAnInputError) {
  const std::vector<RasterCell> cells = {{0, 0}, {1, 0}, {0, 1}, {1, 0}};
  try {
    GridCellTriangles(cells, "dem.tif");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "dem.tif: two samples have raster cell (1, 0)");
  }
}

TEST(RemapGridTrianglesTest, CellsWithADroppedCornerGo) {
  const Samples s = Lattice(3, 2, {}, NorthUp);  // cells (0, 0), (1, 0)
  std::vector<int32_t> t = GridCellTriangles(s.cells, "grid");
  // Reverse the order, and drop sample (0, 0): only cell (1, 0) is left.
  std::vector<int32_t> new_index = {-1, 4, 3, 2, 1, 0};
  RemapGridTriangles(new_index, &t);
  EXPECT_EQ(t, (std::vector<int32_t>{4, 3, 0, 4, 0, 1}));
}

// Exact lattices (every cell cocircular: Delaunay is all ties), rows going
// down or up, turned, mirrored: every cell is kept, split by the rule, and
// every interior node has six triangles.
TEST(EnforceGridTest, EveryCellByTheRuleInAnyOrientation) {
  const double turn = 0.5235987755982988;  // 30°
  const std::vector<std::pair<const char*, std::function<Point2(int, int)>>> placements = {
      {"north-up", NorthUp},
      {"rows up", [](int c, int r) { return Point2{3.0 * c, 1.5 * r}; }},
      {"mirrored", [](int c, int r) { return Point2{-2.0 * c, -2.0 * r}; }},
      {"turned", [&](int c, int r) {
         return Point2{431234.5 + 0.3 * (c * std::cos(turn) - r * std::sin(turn)),
                       6123456.7 - 0.3 * (c * std::sin(turn) + r * std::cos(turn))};
       }}};
  for (const auto& [name, place] : placements) {
    const Samples s = Lattice(12, 9, {{5, 4}}, place);
    Triangulation mesh = Triangulate(s.xy);
    GridMeshStats stats;
    const std::vector<uint8_t> in_grid =
        EnforceGrid(s.xy, GridCellTriangles(s.cells, "grid"), &mesh, &stats);
    ExpectValidMesh(s.xy, mesh);
    EXPECT_EQ(stats.cells, 11 * 8 - 4) << name;
    EXPECT_EQ(stats.folded_cells, 0) << name;
    EXPECT_EQ(stats.dropped_cells, 0) << name;
    EXPECT_EQ(std::count(in_grid.begin(), in_grid.end(), 1), 2 * stats.cells) << name;
    std::vector<int> triangles_at(s.xy.size(), 0);
    for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
      if (!in_grid[t]) continue;
      const int32_t* v = &mesh.triangles[3 * t];
      // The cell's diagonal (c, r)-(c+1, r+1) is an edge of both halves.
      int c = INT32_MAX, r = INT32_MAX;
      for (int i = 0; i < 3; ++i) {
        c = std::min(c, s.cells[v[i]].column), r = std::min(r, s.cells[v[i]].row);
        ++triangles_at[v[i]];
      }
      int on_diagonal = 0;
      for (int i = 0; i < 3; ++i) {
        const RasterCell& p = s.cells[v[i]];
        on_diagonal += (p.column == c && p.row == r) || (p.column == c + 1 && p.row == r + 1);
      }
      EXPECT_EQ(on_diagonal, 2) << name << ": cell " << c << ", " << r;
    }
    for (std::size_t i = 0; i < s.xy.size(); ++i) {
      const RasterCell& p = s.cells[i];
      const bool interior = p.column > 0 && p.row > 0 && p.column < 11 && p.row < 8 &&
                            std::abs(p.column - 5) + std::abs(p.row - 4) > 1 &&
                            !(std::abs(p.column - 5) == 1 && std::abs(p.row - 4) == 1);
      if (interior) {
        EXPECT_EQ(triangles_at[i], 6) << name << ": " << p.column << ", " << p.row;
      }
    }
  }
}

// Sample (4, 4) of a unit lattice moved into cell (5, 5): the cells around it
// fold. Those with a triangle turned over, and every cell sharing a corner
// with one, are left out; the rest stay, and the mesh stays valid.
TEST(EnforceGridTest, FoldedCellsAndTheirNeighboursAreLeftOut) {
  Samples s = Lattice(10, 10, {}, [](int c, int r) { return Point2{1.0 * c, 1.0 * r}; });
  s.xy[4 * 10 + 4] = {5.4, 5.3};
  const std::vector<int32_t> cells = GridCellTriangles(s.cells, "grid");
  // Expected, from exact signs: a cell folds when a half is not counter-clockwise.
  std::set<Cell> folded, dropped;
  for (std::size_t k = 0; k < cells.size(); k += 6) {
    const int32_t* v = &cells[k];
    if (Orient2D(s.xy[v[0]], s.xy[v[1]], s.xy[v[2]]) > 0 &&
        Orient2D(s.xy[v[3]], s.xy[v[4]], s.xy[v[5]]) > 0) {
      continue;
    }
    folded.insert({s.cells[v[0]].column, s.cells[v[0]].row});
  }
  ASSERT_FALSE(folded.empty());
  for (int r = 0; r < 9; ++r) {
    for (int c = 0; c < 9; ++c) {
      for (const auto& [fc, fr] : folded) {
        if (std::abs(c - fc) <= 1 && std::abs(r - fr) <= 1) dropped.insert({c, r});
      }
    }
  }
  Triangulation mesh = Triangulate(s.xy);
  GridMeshStats stats;
  const std::vector<uint8_t> in_grid = EnforceGrid(s.xy, cells, &mesh, &stats);
  ExpectValidMesh(s.xy, mesh);
  EXPECT_EQ(stats.cells, 81);
  EXPECT_EQ(stats.folded_cells, static_cast<int64_t>(folded.size()));
  EXPECT_EQ(stats.dropped_cells, static_cast<int64_t>(dropped.size()));
  const std::set<Cell> kept = KeptCells(s, mesh, in_grid);
  for (int r = 0; r < 9; ++r) {
    for (int c = 0; c < 9; ++c) {
      EXPECT_EQ(kept.count({c, r}), dropped.count({c, r}) ? 0u : 1u) << c << ", " << r;
    }
  }
  EXPECT_TRUE(dropped.count({5, 5})) << "the cell the sample landed in";
  std::printf("fold: %lld cells folded, %lld left out of 81\n",
              static_cast<long long>(stats.folded_cells),
              static_cast<long long>(stats.dropped_cells));

  // Measured, such a raster's data domain is the cells kept (unit squares).
  std::vector<std::array<double, 3>> points, flat;
  for (std::size_t i = 0; i < s.xy.size(); ++i) {
    points.push_back({s.xy[i].x, s.xy[i].y, 0.0});
    flat.push_back({s.xy[i].x, s.xy[i].y, 1.0});
  }
  Surface a = MakeSurface(points, {}, "folded"), b = MakeSurface(flat, {}, "flat");
  a.raster_cell = s.cells;
  const MeasureSummary m = Measure(a, b);
  EXPECT_NEAR(m.domain_area_a, static_cast<double>(kept.size()), 1e-12);
  EXPECT_NEAR(m.rho_d, m.overlap_area, 1e-12);  // d = 1 on Ω
}

// A sample carried far across the grid lands inside a cell no fold is next
// to: that cell cannot be forced in (it would contain a vertex) and is left
// out too; the mesh stays valid and the cells away from both stay.
TEST(EnforceGridTest, ACellThatCannotBeForcedInIsLeftOut) {
  Samples s = Lattice(12, 12, {}, [](int c, int r) { return Point2{1.0 * c, 1.0 * r}; });
  s.xy[2 * 12 + 2] = {8.5, 8.25};  // into cell (8, 8)
  Triangulation mesh = Triangulate(s.xy);
  GridMeshStats stats;
  const std::vector<uint8_t> in_grid =
      EnforceGrid(s.xy, GridCellTriangles(s.cells, "grid"), &mesh, &stats);
  ExpectValidMesh(s.xy, mesh);
  const std::set<Cell> kept = KeptCells(s, mesh, in_grid);
  EXPECT_EQ(kept.count({8, 8}), 0u);
  EXPECT_GT(stats.dropped_cells, stats.folded_cells);
  for (const Cell& far : std::vector<Cell>{{0, 10}, {10, 0}, {5, 5}, {10, 10}, {6, 8}}) {
    EXPECT_EQ(kept.count(far), 1u) << far.first << ", " << far.second;
  }
  EXPECT_EQ(static_cast<int64_t>(kept.size()), stats.cells - stats.dropped_cells);
}

TEST(EnforceGridTest, CallerErrors) {
  const Samples s = Lattice(3, 3, {}, NorthUp);
  Triangulation mesh = Triangulate(s.xy);
  EXPECT_THROW(EnforceGrid(s.xy, {0, 1, 4, 0, 4}, &mesh), std::invalid_argument);
}

}  // namespace
}  // namespace surfreg

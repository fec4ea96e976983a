// The data domain of a sampled surface (measure/domain.h): raster cells with
// four corners (on the grid mesh, measure/grid_mesh.h), scattered clouds with
// voids, and the convex hull.
#include "measure/domain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/grid_mesh.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

double TriangleArea(const std::vector<Point2>& xy, const Triangulation& mesh, int32_t t) {
  const Point2& a = xy[mesh.triangles[3 * t]];
  const Point2& b = xy[mesh.triangles[3 * t + 1]];
  const Point2& c = xy[mesh.triangles[3 * t + 2]];
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

// A raster's valid cell centres: `columns` x `rows` cells of dx by dy, the
// cells in `missing` (column, row) nodata.
struct Lattice {
  int columns = 40, rows = 40;
  double x0 = 1000.5, y0 = -200.25, dx = 2.0, dy = 1.5;
  std::set<std::pair<int, int>> missing;

  bool Has(int c, int r) const {
    return c >= 0 && r >= 0 && c < columns && r < rows && missing.count({c, r}) == 0;
  }
  std::vector<Point2> Points() const {
    std::vector<Point2> xy;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < columns; ++c) {
        if (Has(c, r)) xy.push_back({x0 + c * dx, y0 + r * dy});
      }
    }
    return xy;
  }
  std::vector<RasterCell> Cells() const {
    std::vector<RasterCell> cells;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < columns; ++c) {
        if (Has(c, r)) cells.push_back({c, r});
      }
    }
    return cells;
  }
  // The grid mesh (Delaunay, the cells forced in) and its grid triangles.
  Triangulation Mesh(const std::vector<Point2>& xy, std::vector<uint8_t>* in_grid) const {
    Triangulation mesh = Triangulate(xy);
    *in_grid = EnforceGrid(xy, GridCellTriangles(Cells(), "lattice"), &mesh);
    return mesh;
  }
  // Cells between sample (c, r) and (c + 1, r + 1) with all four corners.
  int CompleteCells() const {
    int n = 0;
    for (int r = 0; r + 1 < rows; ++r) {
      for (int c = 0; c + 1 < columns; ++c) {
        n += Has(c, r) && Has(c + 1, r) && Has(c, r + 1) && Has(c + 1, r + 1);
      }
    }
    return n;
  }
};

Lattice HolesAndStrip() {
  Lattice lattice;
  for (const auto& pixel : std::vector<std::pair<int, int>>{
           {5, 5}, {12, 30}, {33, 8}, {0, 17}, {39, 39}, {25, 36}, {8, 21}}) {
    lattice.missing.insert(pixel);
  }
  for (int c = 18; c < 21; ++c) {  // a void strip 3 cells wide, rows 6 to 33
    for (int r = 6; r < 34; ++r) lattice.missing.insert({c, r});
  }
  for (int c = 28; c < 30; ++c) {  // and a 2 x 2 block
    for (int r = 20; r < 22; ++r) lattice.missing.insert({c, r});
  }
  return lattice;
}

TEST(DataDomainTest, GridKeepsExactlyTheCellsWithFourCorners) {
  const Lattice lattice = HolesAndStrip();
  const std::vector<Point2> xy = lattice.Points();
  std::vector<uint8_t> in_grid;
  const Triangulation mesh = lattice.Mesh(xy, &in_grid);
  DomainRule rule;
  rule.grid = true;
  const std::vector<uint8_t> in = DataDomain(xy, mesh, rule, &in_grid);
  ASSERT_EQ(in.size(), static_cast<std::size_t>(mesh.num_triangles()));
  const int complete = lattice.CompleteCells();
  // 39 x 39 cells; lost: 4 per inner pixel, 2 at the edge, 1 in the corner,
  // 4 x 29 to the strip, 3 x 3 to the block.
  ASSERT_EQ(complete, 1521 - 5 * 4 - 2 - 1 - 4 * 29 - 9);
  // Every kept triangle is half of a complete cell, and every complete cell
  // has both halves kept.
  std::set<std::pair<int, int>> halves_seen;
  int kept = 0;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!in[t]) continue;
    ++kept;
    const int32_t* v = &mesh.triangles[3 * t];
    const double cx = (xy[v[0]].x + xy[v[1]].x + xy[v[2]].x) / 3.0;
    const double cy = (xy[v[0]].y + xy[v[1]].y + xy[v[2]].y) / 3.0;
    const int c = static_cast<int>(std::floor((cx - lattice.x0) / lattice.dx));
    const int r = static_cast<int>(std::floor((cy - lattice.y0) / lattice.dy));
    EXPECT_TRUE(lattice.Has(c, r) && lattice.Has(c + 1, r) && lattice.Has(c, r + 1) &&
                lattice.Has(c + 1, r + 1))
        << "triangle " << t << " in cell " << c << ", " << r;
    EXPECT_NEAR(TriangleArea(xy, mesh, t), 0.5 * lattice.dx * lattice.dy, 1e-9);
    // Split along the diagonal from sample (c, r) to (c + 1, r + 1).
    const Point2 from{lattice.x0 + c * lattice.dx, lattice.y0 + r * lattice.dy};
    const Point2 to{from.x + lattice.dx, from.y + lattice.dy};
    int on_diagonal = 0;
    for (int i = 0; i < 3; ++i) {
      on_diagonal += (xy[v[i]].x == from.x && xy[v[i]].y == from.y) ||
                     (xy[v[i]].x == to.x && xy[v[i]].y == to.y);
    }
    EXPECT_EQ(on_diagonal, 2) << "triangle " << t << " in cell " << c << ", " << r;
    halves_seen.insert({c, r});
  }
  EXPECT_EQ(kept, 2 * complete);
  EXPECT_EQ(static_cast<int>(halves_seen.size()), complete);
  EXPECT_NEAR(DomainArea(xy, mesh, in), complete * lattice.dx * lattice.dy, 1e-7);
}

TEST(DataDomainTest, GridWithoutHolesIsTheWholeHull) {
  Lattice lattice;
  lattice.columns = 17, lattice.rows = 9;
  const std::vector<Point2> xy = lattice.Points();
  std::vector<uint8_t> in_grid;
  const Triangulation mesh = lattice.Mesh(xy, &in_grid);
  DomainRule rule;
  rule.grid = true;
  const std::vector<uint8_t> in = DataDomain(xy, mesh, rule, &in_grid);
  EXPECT_EQ(std::count(in.begin(), in.end(), 1), mesh.num_triangles());
  EXPECT_NEAR(DomainArea(xy, mesh, in), MeshArea(xy, mesh), 1e-9);
  // A raster's domain is its grid triangles: without them it is a caller error.
  EXPECT_THROW(DataDomain(xy, mesh, rule), std::invalid_argument);
}

// Distance from p to a triangle (0 inside).
double DistanceToTriangle(const Point2& p, const Point2 t[3]) {
  double best = HUGE_VAL;
  int sign = 0;
  for (int i = 0; i < 3; ++i) {
    const Point2& a = t[i];
    const Point2& b = t[(i + 1) % 3];
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double s =
        std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    best = std::min(best, std::hypot(p.x - a.x - s * ex, p.y - a.y - s * ey));
    const double cross = ex * (p.y - a.y) - ey * (p.x - a.x);
    sign += cross >= 0;
  }
  return sign == 3 || sign == 0 ? 0.0 : best;
}

// In chunks of vertices and triangles (several at 40000 points): the same
// domain on any number of threads, with a void and outline slivers to cut.
TEST(DataDomainTest, SameDomainOnOneTwoAndEightThreads) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 200.0);
  std::vector<Point2> xy;
  while (xy.size() < 40000) {
    const Point2 p{u(rng), u(rng)};
    if (std::hypot(p.x - 80, p.y - 120) > 30) xy.push_back(p);
  }
  const Triangulation mesh = Triangulate(xy);
  const std::vector<uint8_t> one = DataDomain(xy, mesh, DomainRule(), nullptr, Execution{1});
  EXPECT_LT(std::count(one.begin(), one.end(), 1), mesh.num_triangles());  // the void is cut out
  for (const int threads : {2, 8}) {
    EXPECT_EQ(DataDomain(xy, mesh, DomainRule(), nullptr, Execution{threads}), one) << threads << " threads";
  }
}

TEST(DataDomainTest, ScatteredCloudWithACircularVoid) {
  for (uint64_t seed : {1u, 2u, 3u}) {
    const double side = 100, cx = 45, cy = 55, radius = 15;
    const int n = 6000;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, side);
    std::vector<Point2> xy;
    while (static_cast<int>(xy.size()) < n) {
      const Point2 p{u(rng), u(rng)};
      if (std::hypot(p.x - cx, p.y - cy) > radius) xy.push_back(p);
    }
    const Triangulation mesh = Triangulate(xy);
    const std::vector<uint8_t> in = DataDomain(xy, mesh);
    const double spacing = std::sqrt(side * side / n);
    // No kept triangle reaches into the void beyond a chord's sagitta: a
    // kept edge spans at most 3 local spacings of the rim.
    for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
      if (!in[t]) continue;
      const Point2 corners[3] = {xy[mesh.triangles[3 * t]], xy[mesh.triangles[3 * t + 1]],
                                 xy[mesh.triangles[3 * t + 2]]};
      EXPECT_GT(DistanceToTriangle({cx, cy}, corners), radius - spacing) << "seed " << seed;
    }
    const double hull = MeshArea(xy, mesh);
    const double expected = hull - kPi * radius * radius;
    const double area = DomainArea(xy, mesh, in);
    EXPECT_NEAR(area / expected, 1.0, 0.03) << "seed " << seed;
    EXPECT_LT(area, hull - 0.9 * kPi * radius * radius) << "seed " << seed;
  }
}

// What is lost is the hull's outline slivers, a band a fraction of a spacing
// wide: 98% of the hull from a few thousand points on.
TEST(DataDomainTest, RandomCloudInARectangleKeepsNearlyTheWholeHull) {
  for (uint64_t seed : {4u, 5u, 6u, 7u}) {
    for (int n : {5000, 50000}) {
      std::mt19937_64 rng(seed);
      std::uniform_real_distribution<double> ux(-30.0, 30.0), uy(10.0, 50.0);
      std::vector<Point2> xy(n);
      for (Point2& p : xy) p = {ux(rng), uy(rng)};
      const Triangulation mesh = Triangulate(xy);
      const std::vector<uint8_t> in = DataDomain(xy, mesh);
      EXPECT_GE(DomainArea(xy, mesh, in), 0.98 * MeshArea(xy, mesh)) << seed << " " << n;
    }
  }
}

TEST(DataDomainTest, HullKeepsEveryTriangle) {
  const Lattice lattice = HolesAndStrip();
  const std::vector<Point2> xy = lattice.Points();
  const Triangulation mesh = Triangulate(xy);
  for (bool grid : {false, true}) {
    DomainRule rule;
    rule.kind = DomainKind::kHull;
    rule.grid = grid;
    const std::vector<uint8_t> in = DataDomain(xy, mesh, rule);
    ASSERT_EQ(in.size(), static_cast<std::size_t>(mesh.num_triangles()));
    EXPECT_EQ(std::count(in.begin(), in.end(), 1), mesh.num_triangles());
    EXPECT_EQ(DomainArea(xy, mesh, in), MeshArea(xy, mesh));
    const std::vector<uint8_t> used = DomainVertices(mesh, xy.size(), in);
    EXPECT_EQ(std::count(used.begin(), used.end(), 1), static_cast<long>(xy.size()));
  }
  EXPECT_STREQ(DomainKindName(DomainKind::kHull), "hull");
  EXPECT_STREQ(DomainKindName(DomainKind::kData), "data");
}

TEST(DataDomainTest, DomainVerticesAreTheCornersOfKeptTriangles) {
  const Lattice lattice = HolesAndStrip();
  const std::vector<Point2> xy = lattice.Points();
  std::vector<uint8_t> in_grid;
  const Triangulation mesh = lattice.Mesh(xy, &in_grid);
  DomainRule rule;
  rule.grid = true;
  const std::vector<uint8_t> in = DataDomain(xy, mesh, rule, &in_grid);
  const std::vector<uint8_t> used = DomainVertices(mesh, xy.size(), in);
  // A sample is a domain vertex iff one of its four cells is complete.
  std::size_t k = 0;
  for (int r = 0; r < lattice.rows; ++r) {
    for (int c = 0; c < lattice.columns; ++c) {
      if (!lattice.Has(c, r)) continue;
      bool corner = false;
      for (int i = -1; i <= 0; ++i) {
        for (int j = -1; j <= 0; ++j) {
          corner = corner || (lattice.Has(c + i, r + j) && lattice.Has(c + i + 1, r + j) &&
                              lattice.Has(c + i, r + j + 1) && lattice.Has(c + i + 1, r + j + 1));
        }
      }
      EXPECT_EQ(used[k], corner ? 1 : 0) << c << ", " << r;
      ++k;
    }
  }
}

// The axial cost's taper is 1 only at inner vertices: on a raster, the
// samples whose four cells are all complete.
TEST(DataDomainTest, InteriorVerticesAreTheSamplesWithFourCompleteCells) {
  const Lattice lattice = HolesAndStrip();
  const std::vector<Point2> xy = lattice.Points();
  std::vector<uint8_t> in_grid;
  const Triangulation mesh = lattice.Mesh(xy, &in_grid);
  DomainRule rule;
  rule.grid = true;
  const std::vector<uint8_t> inner =
      InteriorVertices(mesh, xy.size(), DataDomain(xy, mesh, rule, &in_grid));
  auto complete = [&](int c, int r) {
    return lattice.Has(c, r) && lattice.Has(c + 1, r) && lattice.Has(c, r + 1) && lattice.Has(c + 1, r + 1);
  };
  std::size_t k = 0;
  int inner_count = 0, outline_count = 0;
  for (int r = 0; r < lattice.rows; ++r) {
    for (int c = 0; c < lattice.columns; ++c) {
      if (!lattice.Has(c, r)) continue;
      const bool all = complete(c - 1, r - 1) && complete(c, r - 1) && complete(c - 1, r) && complete(c, r);
      EXPECT_EQ(inner[k], all ? 1 : 0) << c << ", " << r;
      (all ? inner_count : outline_count)++;
      ++k;
    }
  }
  EXPECT_GT(inner_count, 1000);
  EXPECT_GT(outline_count, 150);
  // The whole hull: only the hull's vertices are not inner.
  const std::vector<uint8_t> hull_inner =
      InteriorVertices(mesh, xy.size(), std::vector<uint8_t>(mesh.num_triangles(), 1));
  k = 0;
  for (int r = 0; r < lattice.rows; ++r) {
    for (int c = 0; c < lattice.columns; ++c) {
      if (!lattice.Has(c, r)) continue;
      const bool border = r == 0 || c == 0 || r == lattice.rows - 1 || c == lattice.columns - 1;
      EXPECT_EQ(hull_inner[k], border ? 0 : 1) << c << ", " << r;
      ++k;
    }
  }
}

}  // namespace
}  // namespace surfreg

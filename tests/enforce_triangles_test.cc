// EnforceTriangles against brute force: the required triangles are faces
// afterwards, the mesh is still a valid triangulation of the hull (checked
// with the exact-arithmetic oracle of tests/testing, not measure/predicates),
// and impossible requests return false without hanging.
#include "measure/enforce_triangles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/locator.h"
#include "tests/testing/delaunay_checks.h"
#include "tests/testing/exact_rational.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

using testing::FilteredOrientSign;
using Triple = std::array<int32_t, 3>;

// The triple rotated so that its smallest index comes first (orientation kept).
Triple Canonical(int32_t a, int32_t b, int32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

std::set<Triple> Faces(const Triangulation& mesh) {
  std::set<Triple> faces;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    faces.insert(Canonical(v[0], v[1], v[2]));
  }
  return faces;
}

int MissingFaces(const Triangulation& mesh, const std::vector<int32_t>& required) {
  const std::set<Triple> faces = Faces(mesh);
  int missing = 0;
  for (std::size_t r = 0; r + 2 < required.size(); r += 3) {
    missing += faces.count(Canonical(required[r], required[r + 1], required[r + 2])) ? 0 : 1;
  }
  return missing;
}

// Whether p lies in the closed triangle (a, b, c), counter-clockwise.
bool InClosedTriangle(const Point2& a, const Point2& b, const Point2& c, const Point2& p) {
  return FilteredOrientSign(a, b, p) >= 0 && FilteredOrientSign(b, c, p) >= 0 &&
         FilteredOrientSign(c, a, p) >= 0;
}

// A valid triangulation of the convex hull of `points`: every triangle
// counter-clockwise (exact), each directed edge in one triangle only,
// neighbors symmetric and across the shared edge, -1 exactly on unpaired
// edges, vertex_triangle holding its vertex, every distinct point used, and
// twice the exact area equal to the hull's.
::testing::AssertionResult IsValidTriangulation(const std::vector<Point2>& points,
                                                const Triangulation& mesh) {
  const auto n = static_cast<int32_t>(points.size());
  const int32_t nt = mesh.num_triangles();
  if (mesh.neighbors.size() != mesh.triangles.size() ||
      mesh.vertex_triangle.size() != points.size()) {
    return ::testing::AssertionFailure() << "array sizes";
  }
  std::map<std::pair<int32_t, int32_t>, std::pair<int32_t, int>> edges;  // (a, b) -> (t, i)
  for (int32_t t = 0; t < nt; ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    for (int i = 0; i < 3; ++i) {
      if (v[i] < 0 || v[i] >= n) return ::testing::AssertionFailure() << "index in " << t;
    }
    if (testing::ExactOrientSign(points[v[0]], points[v[1]], points[v[2]]) <= 0) {
      return ::testing::AssertionFailure() << "triangle " << t << " not counter-clockwise";
    }
    for (int i = 0; i < 3; ++i) {
      if (!edges.emplace(std::make_pair(v[(i + 1) % 3], v[(i + 2) % 3]), std::make_pair(t, i))
               .second) {
        return ::testing::AssertionFailure() << "directed edge twice (overlap), triangle " << t;
      }
    }
  }
  for (const auto& [edge, where] : edges) {
    const int32_t u = mesh.neighbors[3 * where.first + where.second];
    const auto twin = edges.find({edge.second, edge.first});
    if (twin == edges.end()) {
      if (u != -1) return ::testing::AssertionFailure() << "unpaired edge has neighbor " << u;
      continue;
    }
    if (u != twin->second.first || mesh.neighbors[3 * u + twin->second.second] != where.first) {
      return ::testing::AssertionFailure() << "neighbors of triangle " << where.first;
    }
  }
  const std::vector<int32_t> rep = testing::LowestIndexOfSameXY(points);
  std::vector<char> used(points.size(), 0);
  for (const int32_t v : mesh.triangles) used[v] = 1;
  for (int32_t v = 0; v < n; ++v) {
    if (rep[v] != v) continue;
    const int32_t t = mesh.vertex_triangle[v];
    if (!used[v]) return ::testing::AssertionFailure() << "vertex " << v << " unused";
    if (t < 0 || t >= nt ||
        (mesh.triangles[3 * t] != v && mesh.triangles[3 * t + 1] != v &&
         mesh.triangles[3 * t + 2] != v)) {
      return ::testing::AssertionFailure() << "vertex_triangle[" << v << "] = " << t;
    }
  }
  testing::Dyadic area;
  for (int32_t t = 0; t < nt; ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    area = area + testing::ExactOrientDet(points[v[0]], points[v[1]], points[v[2]]);
  }
  if (area != testing::TwiceArea(points, testing::ConvexHullWithCollinear(points))) {
    return ::testing::AssertionFailure() << "area differs from the convex hull's";
  }
  return ::testing::AssertionSuccess();
}

// Each query lies in exactly the triangles that LocatePointBruteForce's
// answer implies: one if strictly inside, two (one on the hull) if on an
// edge; the vertices are found as themselves. Catches overlaps and gaps.
::testing::AssertionResult LocatesConsistently(const std::vector<Point2>& points,
                                               const Triangulation& mesh,
                                               const std::vector<Point2>& queries) {
  for (const Point2& p : queries) {
    const Location loc = LocatePointBruteForce(points, mesh, p);
    if (!loc.found()) return ::testing::AssertionFailure() << "not found " << testing::Str(p);
    int containing = 0;
    bool has_answer = false;
    for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
      const int32_t* v = &mesh.triangles[3 * t];
      if (InClosedTriangle(points[v[0]], points[v[1]], points[v[2]], p)) {
        ++containing;
        has_answer = has_answer || t == loc.triangle;
      }
    }
    const bool ok = loc.where == Where::kInside   ? containing == 1
                    : loc.where == Where::kOnEdge ? (containing == 1 || containing == 2)
                                                  : containing >= 1;
    if (!ok || !has_answer) {
      return ::testing::AssertionFailure() << testing::Str(p) << " in " << containing
                                           << " triangles, locator says " << loc.triangle;
    }
  }
  for (int32_t v = 0; v < static_cast<int32_t>(points.size()); ++v) {
    if (mesh.vertex_triangle[v] < 0) continue;
    const Location loc = LocatePointBruteForce(points, mesh, points[v]);
    if (loc.where != Where::kOnVertex || mesh.triangles[3 * loc.triangle + loc.index] != v) {
      return ::testing::AssertionFailure() << "vertex " << v << " not located as itself";
    }
  }
  return ::testing::AssertionSuccess();
}

std::vector<Point2> RandomQueries(const std::vector<Point2>& points, int count, uint64_t seed) {
  double x0 = points[0].x, x1 = x0, y0 = points[0].y, y1 = y0;
  for (const Point2& p : points) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  std::vector<Point2> queries;
  const std::vector<int32_t> hull = testing::ConvexHullWithCollinear(points);
  while (static_cast<int>(queries.size()) < count) {
    const Point2 q = {ux(rng), uy(rng)};
    bool inside = true;
    for (std::size_t k = 0; k < hull.size() && inside; ++k) {
      inside = FilteredOrientSign(points[hull[k]], points[hull[(k + 1) % hull.size()]], q) > 0;
    }
    if (inside) queries.push_back(q);
  }
  return queries;
}

// The triangles of `mesh` that are counter-clockwise at `moved` and hold no
// other moved point (inside or on an edge), by brute force.
std::vector<int32_t> StillValidTriangles(const Triangulation& mesh,
                                         const std::vector<Point2>& moved) {
  std::vector<int32_t> kept;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    const Point2 &a = moved[v[0]], &b = moved[v[1]], &c = moved[v[2]];
    if (FilteredOrientSign(a, b, c) <= 0) continue;
    const double x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
    const double y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
    bool empty = true;
    for (int32_t w = 0; w < static_cast<int32_t>(moved.size()) && empty; ++w) {
      const Point2& p = moved[w];
      if (w == v[0] || w == v[1] || w == v[2] || p.x < x0 || p.x > x1 || p.y < y0 || p.y > y1) {
        continue;
      }
      empty = !InClosedTriangle(a, b, c, p);
    }
    if (empty) kept.insert(kept.end(), v, v + 3);
  }
  return kept;
}

// Number of mesh edges that properly cross segment ab.
int CrossingCount(const std::vector<Point2>& points, const Triangulation& mesh, int32_t a,
                  int32_t b) {
  int count = 0;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t c = mesh.triangles[3 * t + i], d = mesh.triangles[3 * t + (i + 1) % 3];
      if (c > d && mesh.neighbors[3 * t + (i + 2) % 3] >= 0) continue;  // each edge once
      const int s1 = FilteredOrientSign(points[a], points[b], points[c]);
      const int s2 = FilteredOrientSign(points[a], points[b], points[d]);
      const int s3 = FilteredOrientSign(points[c], points[d], points[a]);
      const int s4 = FilteredOrientSign(points[c], points[d], points[b]);
      count += (s1 * s2 < 0 && s3 * s4 < 0) ? 1 : 0;
    }
  }
  return count;
}

// Enforces and checks everything that must hold on success.
void EnforceAndCheck(const std::vector<Point2>& points, const std::vector<int32_t>& required,
                     Triangulation* mesh, const std::string& what) {
  ASSERT_TRUE(EnforceTriangles(points, required, mesh)) << what;
  EXPECT_EQ(MissingFaces(*mesh, required), 0) << what;
  EXPECT_TRUE(IsValidTriangulation(points, *mesh)) << what;
  EXPECT_NEAR(MeshArea(points, *mesh), MeshArea(points, Triangulate(points)),
              1e-12 * std::fabs(MeshArea(points, *mesh)))
      << what;
}

// ---------------------------------------------------------------------------

TEST(EnforceTrianglesTest, RandomPointsAfterShear) {
  const std::vector<Point2> points = testing::UniformPoints(2000, 17);
  const Triangulation original = Triangulate(points);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> noise(-1e-4, 1e-4);
  std::vector<Point2> moved(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point2& p = points[i];
    moved[i] = {p.x + 0.025 * p.y + noise(rng), p.y + 0.012 * p.x + noise(rng)};
  }
  std::vector<int32_t> required = StillValidTriangles(original, moved);
  for (std::size_t r = 0; r < required.size(); r += 3) {  // any rotation of a triple is accepted
    std::rotate(&required[r], &required[r + (r / 3) % 3], &required[r + 3]);
  }
  Triangulation mesh = Triangulate(moved);
  const int missing_before = MissingFaces(mesh, required);
  ASSERT_GT(missing_before, 10) << "the perturbation should change the Delaunay in places";
  EnforceAndCheck(moved, required, &mesh, "sheared uniform points");
  EXPECT_TRUE(LocatesConsistently(moved, mesh, RandomQueries(moved, 300, 3)));
  // Enforcing again is a no-op that still succeeds.
  const std::vector<int32_t> before = mesh.triangles;
  EXPECT_TRUE(EnforceTriangles(moved, required, &mesh));
  EXPECT_EQ(mesh.triangles, before);
}

// The triangles of an affinely stretched point set's Delaunay, pulled back:
// a valid triangulation of the original points (an affine map preserves
// orientation and incidence) full of long thin triangles that cross many
// Delaunay edges. Enforcing all of them must reproduce it exactly.
TEST(EnforceTrianglesTest, WholeStretchedTriangulationIsRecovered) {
  struct Case {
    std::vector<Point2> points;
    double a, b, c, d;  // the linear map (x, y) -> (a x + b y, c x + d y), det > 0
    std::string what;
  };
  const std::vector<Case> cases = {
      {testing::UniformPoints(800, 21), 12.0, 0.0, 0.0, 1.0, "uniform, x stretched 12"},
      {testing::UniformPoints(800, 22), 1.0, 6.0, 0.0, 1.0, "uniform, sheared 6"},
      {testing::ClusteredPoints(600, 5, 1e-2, 23), 1.0, 0.0, 3.0, 20.0, "clustered"},
      {testing::GridPoints(20, 20), 1.0, 3.0, 0.0, 1.0, "grid sheared 3"},
      {testing::GridPoints(20, 20), 3.0, 2.0, 1.0, 1.0, "grid, unimodular map (3 2; 1 1)"},
  };
  for (const Case& c : cases) {
    std::vector<Point2> stretched;
    for (const Point2& p : c.points)
      stretched.push_back({c.a * p.x + c.b * p.y, c.c * p.x + c.d * p.y});
    const Triangulation target = Triangulate(stretched);
    Triangulation mesh = Triangulate(c.points);
    ASSERT_GT(MissingFaces(mesh, target.triangles), 20) << c.what;
    EnforceAndCheck(c.points, target.triangles, &mesh, c.what);
    EXPECT_EQ(Faces(mesh), Faces(target)) << c.what;
  }
}

// Long thin required triangles whose long edge crosses many Delaunay edges:
// a zigzag strip, then a fan.
TEST(EnforceTrianglesTest, ThinTrianglesAcrossZigzagAndFan) {
  std::vector<Point2> points = {{0.0, 0.0}, {10.0, 0.0}, {5.0, -0.05}};
  for (int i = 0; i < 10; ++i) points.push_back({i + 0.5, 0.3});
  for (int i = 1; i < 10; ++i) points.push_back({static_cast<double>(i), -0.6});
  points.push_back({5.0, 4.0});  // one far point, so the hull is not just the strip
  Triangulation mesh = Triangulate(points);
  const std::vector<int32_t> required = {0, 2, 1};
  ASSERT_EQ(MissingFaces(mesh, required), 1);
  ASSERT_GE(CrossingCount(points, mesh, 0, 1), 5);
  EnforceAndCheck(points, required, &mesh, "thin triangle");
  EXPECT_TRUE(LocatesConsistently(points, mesh, RandomQueries(points, 200, 4)));

  // A fan: apex (0, 0) joined to points on an arc of radius 10 above; the
  // required triangle (u, apex, v) is flat with u, v at height 1 far left
  // and right, so its top edge u-v crosses the fan's edges.
  std::vector<Point2> fan = {{-9.0, 1.0}, {0.0, 0.0}, {9.0, 1.0}};
  for (int i = -6; i <= 6; ++i) {
    const double angle = i * 10.0 * M_PI / 180.0;
    fan.push_back({10.0 * std::sin(angle), 10.0 * std::cos(angle)});
  }
  Triangulation fan_mesh = Triangulate(fan);
  const std::vector<int32_t> flat = {0, 1, 2};
  ASSERT_EQ(MissingFaces(fan_mesh, flat), 1);
  ASSERT_GE(CrossingCount(fan, fan_mesh, 0, 2), 5);
  EnforceAndCheck(fan, flat, &fan_mesh, "fan");
  EXPECT_TRUE(LocatesConsistently(fan, fan_mesh, RandomQueries(fan, 200, 5)));
}

TEST(EnforceTrianglesTest, ImpossibleRequestsReturnFalse) {
  // 0..3 a square, 4 inside it, 5 in the middle of its bottom edge 0-1, 6
  // above the top edge.
  const std::vector<Point2> points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1.5}, {2, 0}, {3, 6}};
  const auto fresh = [&] { return Triangulate(points); };
  const auto expect_false = [&](const std::vector<int32_t>& required, const std::string& what) {
    Triangulation mesh = fresh();
    EXPECT_FALSE(EnforceTriangles(points, required, &mesh)) << what;
    EXPECT_TRUE(IsValidTriangulation(points, mesh)) << what;
    return mesh;
  };
  expect_false({0, 2, 3}, "contains vertex 4");
  expect_false({0, 1, 3}, "vertex 5 on edge 0-1 and 4 inside");
  expect_false({0, 1, 2}, "edge 0-1 passes through vertex 5");
  expect_false({5, 1, 2, 0, 1, 2}, "0-1-2 holds 5-1-2 and vertex 5");
  expect_false({0, 3, 2}, "clockwise");
  expect_false({0, 5, 5}, "degenerate");
  expect_false({0, 5, 99}, "index out of range");
  // Overlapping, each triangle empty on its own: two on the same side of a
  // shared edge; two whose edges 2-5 and 1-3 cross; three of which two overlap.
  expect_false({1, 2, 4, 1, 2, 5}, "same side of 1-2");
  expect_false({5, 1, 2, 1, 6, 3}, "edges 2-5 and 1-3 cross");
  expect_false({4, 5, 1, 5, 1, 2, 4, 1, 2}, "4-1-2 overlaps 5-1-2");

  // A clockwise request does not stop the valid ones.
  Triangulation mesh = fresh();
  EXPECT_FALSE(EnforceTriangles(points, {0, 3, 4, 5, 2, 4}, &mesh));
  EXPECT_EQ(MissingFaces(mesh, {5, 2, 4}), 0);
  EXPECT_TRUE(IsValidTriangulation(points, mesh));
}

// Whether two counter-clockwise triangles have disjoint interiors: some edge
// line of one has the other entirely on its closed outer side (separating
// axis theorem for convex polygons).
bool InteriorsDisjoint(const std::vector<Point2>& p, const int32_t* s, const int32_t* t) {
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < 3; ++i) {
      const Point2 &a = p[s[i]], &b = p[s[(i + 1) % 3]];
      if (FilteredOrientSign(a, b, p[t[0]]) <= 0 && FilteredOrientSign(a, b, p[t[1]]) <= 0 &&
          FilteredOrientSign(a, b, p[t[2]]) <= 0) {
        return true;
      }
    }
    std::swap(s, t);
  }
  return false;
}

// Whether some triangulation of `points` has all of `required` as faces: each
// triangle counter-clockwise and holding no other point (closed), distinct
// triangles with disjoint interiors (then their edges do not cross and
// extend to a triangulation). Brute force.
bool Feasible(const std::vector<Point2>& points, const std::vector<int32_t>& required) {
  const auto n = static_cast<int32_t>(points.size());
  std::set<Triple> distinct;
  for (std::size_t r = 0; r < required.size(); r += 3) {
    const int32_t* v = &required[r];
    for (int i = 0; i < 3; ++i) {
      if (v[i] < 0 || v[i] >= n) return false;
    }
    if (FilteredOrientSign(points[v[0]], points[v[1]], points[v[2]]) <= 0) return false;
    for (int32_t w = 0; w < n; ++w) {
      if (w != v[0] && w != v[1] && w != v[2] &&
          InClosedTriangle(points[v[0]], points[v[1]], points[v[2]], points[w])) {
        return false;
      }
    }
    distinct.insert(Canonical(v[0], v[1], v[2]));
  }
  for (auto i = distinct.begin(); i != distinct.end(); ++i) {
    for (auto j = std::next(i); j != distinct.end(); ++j) {
      if (!InteriorsDisjoint(points, i->data(), j->data())) return false;
    }
  }
  return true;
}

// Random small triangles (a vertex and two points near it, either order) and
// a few arbitrary triples: EnforceTriangles must say true exactly when the
// brute-force feasibility check does, keep the mesh valid, and return
// promptly on the impossible ones.
void CheckRandomRequests(const std::vector<Point2>& points, double radius, uint64_t seed,
                         const std::string& what) {
  const auto n = static_cast<int32_t>(points.size());
  std::vector<std::vector<int32_t>> near(points.size());
  for (int32_t i = 0; i < n; ++i) {
    for (int32_t j = 0; j < n; ++j) {
      if (j != i && std::hypot(points[i].x - points[j].x, points[i].y - points[j].y) < radius) {
        near[i].push_back(j);
      }
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int32_t> index(0, n - 1);
  const auto start = std::chrono::steady_clock::now();
  int feasible_count = 0, infeasible_count = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Triangulation mesh = Triangulate(points);
    std::vector<int32_t> required;
    for (int k = 0; k < 1 + trial % 3; ++k) {
      const int32_t a = index(rng);
      if (trial % 10 == 9 || near[a].size() < 2) {
        required.insert(required.end(), {a, index(rng), index(rng)});
        continue;
      }
      std::uniform_int_distribution<std::size_t> pick(0, near[a].size() - 1);
      int32_t b = near[a][pick(rng)], c = near[a][pick(rng)];
      // Mostly counter-clockwise, so that the feasible ones are not rare.
      if (trial % 4 != 0 && FilteredOrientSign(points[a], points[b], points[c]) < 0)
        std::swap(b, c);
      required.insert(required.end(), {a, b, c});
    }
    const bool feasible = Feasible(points, required);
    (feasible ? feasible_count : infeasible_count) += 1;
    const bool ok = EnforceTriangles(points, required, &mesh);
    EXPECT_EQ(ok, feasible) << what << ", trial " << trial;
    if (ok) {
      EXPECT_EQ(MissingFaces(mesh, required), 0) << what << ", trial " << trial;
    }
    ASSERT_TRUE(IsValidTriangulation(points, mesh)) << what << ", trial " << trial;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 60.0) << what;
  EXPECT_GE(feasible_count, 30) << what;
  EXPECT_GE(infeasible_count, 30) << what;
}

TEST(EnforceTrianglesTest, RandomRequestsMatchBruteForceFeasibility) {
  CheckRandomRequests(testing::UniformPoints(400, 31), 0.1, 8, "uniform");
  // Lattice: collinear triples, vertices exactly on required edges.
  CheckRandomRequests(testing::GridPoints(16, 16), 1.5, 9, "grid");
}

// Cocircular cells: the Delaunay diagonal of each cell follows the tie rule;
// require the other one in some cells, and long empty lattice triangles
// (area 1/2, so no other lattice point by Pick's theorem) elsewhere.
TEST(EnforceTrianglesTest, GridOtherDiagonalsAndLatticeSlivers) {
  const int n = 30;
  const std::vector<Point2> points = testing::GridPoints(n, n);
  const auto id = [&](int c, int r) { return r * n + c; };
  Triangulation mesh = Triangulate(points);
  std::set<std::pair<int32_t, int32_t>> edges;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t a = mesh.triangles[3 * t + i], b = mesh.triangles[3 * t + (i + 1) % 3];
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  }
  std::vector<int32_t> required;
  int flipped_cells = 0;
  for (int r = 0; r < 18; ++r) {
    for (int c = 0; c < n - 1; ++c) {
      if ((c + 2 * r) % 3 != 0) continue;
      const int32_t p00 = id(c, r), p10 = id(c + 1, r), p01 = id(c, r + 1), p11 = id(c + 1, r + 1);
      if (edges.count({p00, p11})) {  // Delaunay chose 00-11: require 10-01
        required.insert(required.end(), {p00, p10, p01, p10, p11, p01});
      } else {
        required.insert(required.end(), {p00, p10, p11, p00, p11, p01});
      }
      ++flipped_cells;
    }
  }
  ASSERT_GT(flipped_cells, 100);
  for (int y : {20, 23, 26}) {
    for (int x : {1, 7, 13, 19, 25}) {
      // Parallelogram (x,y) (x+1,y) (x+3,y+1) (x+2,y+1) as two unimodular triangles.
      required.insert(required.end(), {id(x, y), id(x + 1, y), id(x + 3, y + 1)});
      required.insert(required.end(), {id(x, y), id(x + 3, y + 1), id(x + 2, y + 1)});
    }
  }
  ASSERT_GE(MissingFaces(mesh, required), flipped_cells);
  EnforceAndCheck(points, required, &mesh, "grid");
  EXPECT_TRUE(LocatesConsistently(points, mesh, RandomQueries(points, 300, 6)));

  // Impossible on the lattice: edge (0,0)-(8,4) runs exactly through the
  // lattice points (2,1), (4,2), (6,3) after crossing other edges.
  Triangulation fresh = Triangulate(points);
  ASSERT_GE(CrossingCount(points, fresh, id(0, 0), id(8, 4)), 2);
  EXPECT_FALSE(EnforceTriangles(points, {id(0, 0), id(8, 4), id(7, 4)}, &fresh));
  EXPECT_TRUE(IsValidTriangulation(points, fresh));
}

}  // namespace
}  // namespace surfreg

// Walking location against brute-force location (every triangle tested with
// exact orientation), on random, grid, rotated-grid and clustered meshes,
// with queries inside, on edges, on vertices, on the hull and outside.
#include "measure/locator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "measure/delaunay.h"
#include "measure/spanning_tree.h"
#include "tests/testing/delaunay_checks.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

// The vertex ids a location pins the point to: 1 for a vertex, 2 for an edge,
// 3 for the interior of a triangle, none outside.
std::set<int32_t> Support(const Triangulation& mesh, const Location& l) {
  std::set<int32_t> ids;
  if (!l.found()) return ids;
  const int32_t* v = &mesh.triangles[3 * l.triangle];
  switch (l.where) {
    case Where::kOnVertex: ids = {v[l.index]}; break;
    case Where::kOnEdge: ids = {v[(l.index + 1) % 3], v[(l.index + 2) % 3]}; break;
    default: ids = {v[0], v[1], v[2]}; break;
  }
  return ids;
}

double Linear(const Point2& p) { return 2.0 * p.x - 3.0 * p.y + 0.5; }

double Interpolate(const std::vector<Point2>& points, const Triangulation& mesh, const Location& l) {
  double value = 0.0;
  for (int i = 0; i < 3; ++i) value += l.barycentric[i] * Linear(points[mesh.triangles[3 * l.triangle + i]]);
  return value;
}

// Queries of every kind for a mesh over `points`.
std::vector<Point2> Queries(const std::vector<Point2>& points, const Triangulation& mesh,
                            uint64_t seed) {
  std::mt19937_64 rng(seed);
  double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
  for (const Point2& p : points) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  const double mx = 0.2 * (hi_x - lo_x), my = 0.2 * (hi_y - lo_y);
  std::uniform_real_distribution<double> ux(lo_x - mx, hi_x + mx), uy(lo_y - my, hi_y + my);
  std::vector<Point2> q;
  for (int k = 0; k < 300; ++k) q.push_back({ux(rng), uy(rng)});  // inside and outside
  std::uniform_int_distribution<int32_t> pick(0, mesh.num_triangles() - 1);
  for (int k = 0; k < 200; ++k) {
    const int32_t t = pick(rng);
    const Point2& a = points[mesh.triangles[3 * t]];
    const Point2& b = points[mesh.triangles[3 * t + 1]];
    q.push_back(a);                                          // on a vertex
    q.push_back({0.5 * a.x + 0.5 * b.x, 0.5 * a.y + 0.5 * b.y});  // on an edge if exact
  }
  // Along hull lines beyond the hull and exactly on hull edges.
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (mesh.neighbors[3 * t + i] >= 0) continue;
      const Point2& a = points[mesh.triangles[3 * t + (i + 1) % 3]];
      const Point2& b = points[mesh.triangles[3 * t + (i + 2) % 3]];
      q.push_back({0.5 * a.x + 0.5 * b.x, 0.5 * a.y + 0.5 * b.y});
      q.push_back({2.0 * b.x - a.x, 2.0 * b.y - a.y});
    }
  }
  return q;
}

void ExpectSameAsBruteForce(const std::vector<Point2>& points, uint64_t seed) {
  const Triangulation mesh = Triangulate(points);
  const std::vector<Point2> queries = Queries(points, mesh, seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_int_distribution<int32_t> pick(0, mesh.num_triangles() - 1);
  int mismatches = 0;
  for (const Point2& q : queries) {
    const Location truth = LocatePointBruteForce(points, mesh, q);
    const Location walk = LocatePoint(points, mesh, q, pick(rng));
    if (walk.where != truth.where || Support(mesh, walk) != Support(mesh, truth)) {
      if (++mismatches <= 5) {
        ADD_FAILURE() << "query (" << q.x << ", " << q.y << "): walk says "
                      << static_cast<int>(walk.where) << " in " << walk.triangle << ", truth "
                      << static_cast<int>(truth.where) << " in " << truth.triangle;
      }
      continue;
    }
    if (truth.found()) {
      // From the containing triangle itself (LocatePoint's shortcut for a
      // point strictly inside; the walk for one on its edges or corners):
      // the same answer as from anywhere, bit for bit inside.
      const Location here = LocatePoint(points, mesh, q, truth.triangle);
      EXPECT_EQ(here.where, walk.where) << "query (" << q.x << ", " << q.y << ")";
      EXPECT_EQ(Support(mesh, here), Support(mesh, walk)) << "query (" << q.x << ", " << q.y << ")";
      if (walk.where == Where::kInside) {
        EXPECT_EQ(here.triangle, walk.triangle);
        EXPECT_EQ(here.barycentric, walk.barycentric);
      }
      EXPECT_NEAR(Interpolate(points, mesh, walk), Linear(q), 1e-9 * (1.0 + std::fabs(Linear(q))))
          << "query (" << q.x << ", " << q.y << ") where " << static_cast<int>(walk.where)
          << " index " << static_cast<int>(walk.index) << " barycentric " << walk.barycentric[0]
          << " " << walk.barycentric[1] << " " << walk.barycentric[2];
      double sum = 0.0;
      for (double b : walk.barycentric) {
        EXPECT_GE(b, 0.0);
        sum += b;
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
    } else {
      // Outside: the walk reports a hull edge where it left.
      ASSERT_GE(walk.triangle, 0);
      EXPECT_EQ(mesh.neighbors[3 * walk.triangle + walk.index], -1);
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(LocatorTest, RandomPoints) {
  for (uint64_t seed : {1, 2, 3}) ExpectSameAsBruteForce(testing::UniformPoints(2000, seed), seed);
}

TEST(LocatorTest, ExactGrid) {
  // Walks along grid lines pass exactly through vertices and along edges.
  ExpectSameAsBruteForce(testing::GridPoints(40, 30), 4);
}

TEST(LocatorTest, RotatedGrid) { ExpectSameAsBruteForce(testing::RotatedGridPoints(30, 30, 30.0), 5); }

TEST(LocatorTest, Clustered) {
  ExpectSameAsBruteForce(testing::ClusteredPoints(2000, 5, 0.01, 6), 6);
}

TEST(LocatorTest, CollinearPlusOne) { ExpectSameAsBruteForce(testing::CollinearPlusOne(50), 7); }

// Queries on grid lines, walked from far away: the segment runs along mesh
// edges and through many vertices.
TEST(LocatorTest, WalksAlongGridLines) {
  const std::vector<Point2> points = testing::GridPoints(20, 20);
  const Triangulation mesh = Triangulate(points);
  for (int x = 0; x < 20; ++x) {
    for (double y : {0.0, 7.5, 19.0, 25.0, -3.0}) {
      const Point2 q{static_cast<double>(x), y};
      const Location truth = LocatePointBruteForce(points, mesh, q);
      for (int32_t start : {0, mesh.num_triangles() / 2, mesh.num_triangles() - 1}) {
        const Location walk = LocatePoint(points, mesh, q, start);
        EXPECT_EQ(walk.where, truth.where) << x << " " << y;
        EXPECT_EQ(Support(mesh, walk), Support(mesh, truth)) << x << " " << y;
      }
    }
  }
}

TEST(LocatorTest, LocateAllInMstOrderMatchesBruteForce) {
  const std::vector<Point2> target = testing::UniformPoints(3000, 11);
  std::vector<Point2> queries = testing::JitteredGridPoints(50, 50, 0.3, 12);
  for (Point2& q : queries) q = {q.x / 49.0 * 1.2 - 0.1, q.y / 49.0 * 1.2 - 0.1};
  queries.push_back(queries[17]);  // a duplicate query
  const Triangulation mesh = Triangulate(target);
  const Triangulation query_mesh = Triangulate(queries);
  const SpanningTree tree = EuclideanMst(queries, query_mesh);
  LocateAllStats stats;
  const std::vector<Location> all = LocateAll(target, mesh, queries, query_mesh, tree, &stats);
  ASSERT_EQ(all.size(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Location truth = LocatePointBruteForce(target, mesh, queries[i]);
    EXPECT_EQ(all[i].where, truth.where) << i;
    EXPECT_EQ(Support(mesh, all[i]), Support(mesh, truth)) << i;
  }
  // Each walk starts next to its tree neighbour: a few triangles per point.
  EXPECT_LT(static_cast<double>(stats.steps) / queries.size(), 12.0);
}

TEST(LocatorTest, LocateAllInChunksMatchesSingleWalksOnAnyThreads) {
  // Over 65 536 queries: several chunks of the tree order.
  const std::vector<Point2> target = testing::UniformPoints(20000, 13);
  std::vector<Point2> queries = testing::UniformPoints(100000, 14);
  for (Point2& q : queries) q = {q.x * 1.1 - 0.05, q.y * 1.1 - 0.05};  // some outside
  const Triangulation mesh = Triangulate(target);
  const Triangulation query_mesh = Triangulate(queries);
  const SpanningTree tree = EuclideanMst(queries, query_mesh);
  LocateAllStats stats;
  const std::vector<Location> all = LocateAll(target, mesh, queries, query_mesh, tree, &stats);
  for (std::size_t i = 0; i < queries.size(); i += 7) {
    const Location truth = LocatePoint(target, mesh, queries[i], 0);
    ASSERT_EQ(all[i].where, truth.where) << i;
    ASSERT_EQ(Support(mesh, all[i]), Support(mesh, truth)) << i;
  }
  EXPECT_LT(static_cast<double>(stats.steps) / queries.size(), 12.0);
  for (int threads : {2, 8}) {
    LocateAllStats many_stats;
    const std::vector<Location> many =
        LocateAll(target, mesh, queries, query_mesh, tree, &many_stats, Execution{threads});
    EXPECT_EQ(many_stats.steps, stats.steps);
    for (std::size_t i = 0; i < queries.size(); ++i) {
      ASSERT_EQ(many[i].triangle, all[i].triangle) << i;
      ASSERT_EQ(many[i].barycentric, all[i].barycentric) << i;
    }
  }
}

// LocateCentroid against brute force on three times the coordinates, where
// the centroid (c0 + c1 + c2) / 3 becomes c0 + c1 + c2, exactly: the points
// are multiples of 2^-20 (lattice points, and random points rounded), so
// tripling and summing them is exact. Frames shifted by whole units give the
// same answer; the rounded centroid does not always (it is off an edge or a
// vertex it lies on).
void ExpectCentroidsExact(const std::vector<Point2>& points, uint64_t seed, int* rounded_wrong) {
  const Triangulation mesh = Triangulate(points);
  std::vector<Point2> tripled;
  for (const Point2& p : points) tripled.push_back({3.0 * p.x, 3.0 * p.y});
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick_point(0, points.size() - 1);
  std::uniform_int_distribution<int32_t> pick(0, mesh.num_triangles() - 1);
  std::uniform_int_distribution<int> shift(-1000, 1000);
  int mismatches = 0;
  for (int k = 0; k < 3000; ++k) {
    std::array<Point2, 3> corners;
    if (k % 2 == 0) {  // three samples: centroids on edges and at vertices are common
      for (Point2& c : corners) c = points[pick_point(rng)];
    } else {  // corners of adjacent triangles of the mesh
      const int32_t t = pick(rng);
      const int32_t u = std::max(0, mesh.neighbors[3 * t + k % 3]);
      corners = {points[mesh.triangles[3 * t]], points[mesh.triangles[3 * t + 1]],
                 points[mesh.triangles[3 * u + (k / 3) % 3]]};
    }
    const Point2 sum{corners[0].x + corners[1].x + corners[2].x,
                     corners[0].y + corners[1].y + corners[2].y};
    const Location truth = LocatePointBruteForce(tripled, mesh, sum);
    for (int frame = 0; frame < 3; ++frame) {
      const Point2 d{frame == 0 ? 0.0 : double(shift(rng)), frame == 0 ? 0.0 : double(shift(rng))};
      std::vector<Point2> moved = points;
      for (Point2& p : moved) p = {p.x + d.x, p.y + d.y};
      std::array<Point2, 3> moved_corners = corners;
      for (Point2& c : moved_corners) c = {c.x + d.x, c.y + d.y};
      const Location exact = LocateCentroid(moved, mesh, moved_corners, pick(rng));
      if (exact.where != truth.where || Support(mesh, exact) != Support(mesh, truth)) {
        if (++mismatches <= 5) {
          ADD_FAILURE() << "centroid of " << testing::Str(corners[0]) << testing::Str(corners[1])
                        << testing::Str(corners[2]) << " in frame " << d.x << " " << d.y
                        << ": where " << static_cast<int>(exact.where) << ", truth "
                        << static_cast<int>(truth.where);
        }
      }
      if (exact.found()) {
        double total = 0.0;
        for (double b : exact.barycentric) total += b;
        EXPECT_NEAR(total, 1.0, 1e-12);
      }
      const Point2 g{(moved_corners[0].x + moved_corners[1].x + moved_corners[2].x) / 3.0,
                     (moved_corners[0].y + moved_corners[1].y + moved_corners[2].y) / 3.0};
      const Location rounded = LocatePoint(moved, mesh, g, 0);
      *rounded_wrong += rounded.where != truth.where || Support(mesh, rounded) != Support(mesh, truth);
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(LocatorTest, CentroidsAreLocatedExactlyInEveryFrame) {
  int rounded_wrong = 0;
  ExpectCentroidsExact(testing::GridPoints(25, 20), 41, &rounded_wrong);
  std::vector<Point2> lattice;  // random lattice points: many collinear triples
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<int> u(-30, 30);
  for (int k = 0; k < 400; ++k) lattice.push_back({double(u(rng)), double(u(rng))});
  ExpectCentroidsExact(lattice, 43, &rounded_wrong);
  std::vector<Point2> quantized = testing::UniformPoints(1500, 44);
  for (Point2& p : quantized) p = {std::ldexp(std::round(std::ldexp(p.x, 20)), -20) * 64,
                                   std::ldexp(std::round(std::ldexp(p.y, 20)), -20) * 64};
  ExpectCentroidsExact(quantized, 45, &rounded_wrong);
  // What the exact location is for: rounded centroids miss edges and
  // vertices they lie on.
  EXPECT_GT(rounded_wrong, 0);
}

TEST(LocatorTest, StartingOnTheQueryVertex) {
  const std::vector<Point2> points = testing::GridPoints(3, 3);
  const Triangulation mesh = Triangulate(points);
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const Location l = LocatePoint(points, mesh, points[mesh.triangles[3 * t]], t);
    EXPECT_EQ(l.where, Where::kOnVertex);
    EXPECT_EQ(l.triangle, t);
    EXPECT_EQ(l.index, 0);
    EXPECT_EQ(l.barycentric[0], 1.0);
  }
}

// A strip of triangles whose two end edges (hull edges, -1) are made to point
// at each other: a walk towards a point far to the right runs off the right
// end into the left end forever. The bound turns that into an internal error.
TEST(LocatorTest, CorruptedAdjacencyThrowsLogicErrorInsteadOfLooping) {
  std::vector<Point2> points;
  for (int i = 0; i <= 5; ++i) {
    points.push_back({double(i), 0.0});
    points.push_back({double(i), 1.0});
  }
  Triangulation mesh = Triangulate(points);
  // The hull edge at x = 0 and the one at x = 5, each as (triangle, local edge).
  int left = -1, right = -1;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (mesh.neighbors[3 * t + i] >= 0) continue;
      const Point2& a = points[mesh.triangles[3 * t + (i + 1) % 3]];
      const Point2& b = points[mesh.triangles[3 * t + (i + 2) % 3]];
      if (a.x == 0 && b.x == 0) left = 3 * t + i;
      if (a.x == 5 && b.x == 5) right = 3 * t + i;
    }
  }
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  mesh.neighbors[left] = right / 3;
  mesh.neighbors[right] = left / 3;
  const Point2 far = {1000.0, 0.6};
  // The valid parts still work: points inside are found as before.
  EXPECT_TRUE(LocatePoint(points, mesh, {2.5, 0.3}, 0).found());
  try {
    LocatePoint(points, mesh, far, 0);
    FAIL() << "no error";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("did not end within " +
                                         std::to_string(WalkStepLimit(mesh)) + " steps"),
              std::string::npos)
        << e.what();
  }
}

TEST(LocatorTest, WalkStepLimitIsFourStepsPerTrianglePlusSlack) {
  Triangulation mesh;
  EXPECT_EQ(WalkStepLimit(mesh), 64);
  mesh.triangles.assign(3 * 1000, 0);
  EXPECT_EQ(WalkStepLimit(mesh), 4064);
}

// On valid meshes no walk comes near the bound, from any start triangle.
TEST(LocatorTest, WalksStayFarBelowTheBound) {
  const std::vector<Point2> points = testing::GridPoints(20, 20);
  const Triangulation mesh = Triangulate(points);
  int most = 0;
  for (int32_t t = 0; t < mesh.num_triangles(); t += 7) {
    for (const Point2& q : {Point2{19.0, 19.0}, Point2{-5.0, 7.0}, Point2{9.5, 9.25}}) {
      int steps = 0;
      LocatePoint(points, mesh, q, t, &steps);
      most = std::max(most, steps);
    }
  }
  EXPECT_LT(most, WalkStepLimit(mesh) / 4);
}

}  // namespace
}  // namespace surfreg

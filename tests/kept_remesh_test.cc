// RemeshAroundKept against what a re-mesh must be: a valid triangulation
// of the kept vertices' convex hull (checked triangle by triangle, and by
// area against the Delaunay triangulation of the same points) that holds
// every kept triangle, in which walks find what a brute-force search finds.
#include "registration/kept_remesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/locator.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

struct Case {
  std::vector<Point2> at_rest, moved;
  Triangulation mesh;       // Delaunay at rest
  std::vector<uint8_t> keep;
};

double EdgeLength(const std::vector<Point2>& p, int32_t a, int32_t b) {
  return std::hypot(p[a].x - p[b].x, p[a].y - p[b].y);
}

// Points of a unit square (random inside, nearly collinear along its edges:
// hull slivers), kept: triangles with every edge shorter than 3 spacings and
// not slivers, outside a disk (a hole) and a strip (a void); then moved as a tilt moves
// a height field's xy (x += 0.05 z, z varying): the slivers turn over.
Case MakeCase(int n, uint32_t seed, bool grid) {
  Case c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), jitter(-1e-7, 1e-7);
  if (grid) {
    const int side = static_cast<int>(std::sqrt(n));
    for (int j = 0; j < side; ++j) {
      for (int i = 0; i < side; ++i) c.at_rest.push_back({i / (side - 1.0), j / (side - 1.0)});
    }
  } else {
    for (int k = 0; k < n; ++k) c.at_rest.push_back({u(rng), u(rng)});
    for (int k = 0; k < n / 50; ++k) {
      const double t = u(rng);
      c.at_rest.push_back({t, jitter(rng)});
      c.at_rest.push_back({1 + jitter(rng), t});
    }
  }
  c.mesh = Triangulate(c.at_rest);
  const double spacing = 1.0 / std::sqrt(static_cast<double>(c.at_rest.size()));
  c.keep.assign(c.mesh.num_triangles(), 0);
  for (int32_t t = 0; t < c.mesh.num_triangles(); ++t) {
    const int32_t* v = &c.mesh.triangles[3 * t];
    const double cx = (c.at_rest[v[0]].x + c.at_rest[v[1]].x + c.at_rest[v[2]].x) / 3;
    const double cy = (c.at_rest[v[0]].y + c.at_rest[v[1]].y + c.at_rest[v[2]].y) / 3;
    const bool short_edges = EdgeLength(c.at_rest, v[0], v[1]) < 3 * spacing &&
                             EdgeLength(c.at_rest, v[1], v[2]) < 3 * spacing &&
                             EdgeLength(c.at_rest, v[2], v[0]) < 3 * spacing;
    const bool in_hole = std::hypot(cx - 0.3, cy - 0.6) < 0.12;
    const bool in_void = cx > 0.6 && cx < 0.65 && cy > 0.2;
    const bool fat = 0.5 * Orient2D(c.at_rest[v[0]], c.at_rest[v[1]], c.at_rest[v[2]]) > 0.05 * spacing * spacing;
    c.keep[t] = short_edges && fat && !in_hole && !in_void;
  }
  for (const Point2& p : c.at_rest) {
    const double z = std::sin(7 * p.x) + 0.5 * std::cos(5 * p.y);
    c.moved.push_back({p.x + 0.002 * z, p.y - 0.0015 * z});
  }
  return c;
}

int FoldedJunk(const Case& c) {
  int folded = 0;
  for (int32_t t = 0; t < c.mesh.num_triangles(); ++t) {
    const int32_t* v = &c.mesh.triangles[3 * t];
    if (!c.keep[t] && Orient2D(c.moved[v[0]], c.moved[v[1]], c.moved[v[2]]) <= 0) ++folded;
  }
  return folded;
}

void ExpectValidRemesh(const Case& c, const Triangulation& out) {
  const auto& p = c.moved;
  const int32_t m = out.num_triangles();
  ASSERT_EQ(out.neighbors.size(), out.triangles.size());
  // Kept triangles first, in order.
  int32_t kept = 0;
  for (int32_t t = 0; t < c.mesh.num_triangles(); ++t) {
    if (!c.keep[t]) continue;
    ASSERT_LT(kept, m);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(out.triangles[3 * kept + i], c.mesh.triangles[3 * t + i]);
    ++kept;
  }
  // Counter-clockwise, neighbors mutual across the same edge, each edge in
  // at most two triangles.
  std::map<std::pair<int32_t, int32_t>, int> directed;
  std::set<int32_t> used;
  double area = 0;
  for (int32_t t = 0; t < m; ++t) {
    const int32_t* v = &out.triangles[3 * t];
    ASSERT_GT(Orient2D(p[v[0]], p[v[1]], p[v[2]]), 0.0) << "triangle " << t;
    area += 0.5 * Orient2D(p[v[0]], p[v[1]], p[v[2]]);
    for (int i = 0; i < 3; ++i) {
      used.insert(v[i]);
      const int32_t a = v[(i + 1) % 3], b = v[(i + 2) % 3];
      EXPECT_EQ(++directed[std::make_pair(a, b)], 1) << "edge " << a << "-" << b << " twice in one direction";
      const int32_t nb = out.neighbors[3 * t + i];
      if (nb < 0) continue;
      const int32_t* w = &out.triangles[3 * nb];
      int back = -1;
      for (int j = 0; j < 3; ++j) {
        if (w[(j + 1) % 3] == b && w[(j + 2) % 3] == a) back = j;
      }
      ASSERT_GE(back, 0) << "triangle " << t << "'s neighbor " << nb << " lacks the edge";
      EXPECT_EQ(out.neighbors[3 * nb + back], t);
    }
  }
  // Every edge without a neighbor is on the hull: the triangles tile the
  // convex hull of the used points, whose area the Delaunay triangulation
  // of those points gives.
  std::vector<Point2> used_points;
  for (int32_t v : used) used_points.push_back(p[v]);
  const double hull = MeshArea(used_points, Triangulate(used_points));
  EXPECT_NEAR(area, hull, 1e-10 * hull);
  for (const auto& [edge, count] : directed) {
    const bool paired = directed.count({edge.second, edge.first}) != 0;
    if (!paired) {
      // A hull edge: every used point on its left or on it.
      for (const Point2& q : used_points) ASSERT_GE(Orient2D(p[edge.first], p[edge.second], q), 0.0);
    }
  }
  ASSERT_EQ(out.vertex_triangle.size(), p.size());
  for (std::size_t v = 0; v < p.size(); ++v) {
    const int32_t t = out.vertex_triangle[v];
    if (used.count(static_cast<int32_t>(v)) == 0) {
      EXPECT_EQ(t, -1);
      continue;
    }
    ASSERT_GE(t, 0);
    EXPECT_TRUE(out.triangles[3 * t] == static_cast<int32_t>(v) || out.triangles[3 * t + 1] == static_cast<int32_t>(v) ||
                out.triangles[3 * t + 2] == static_cast<int32_t>(v));
  }
  // Walks from one corner find the triangle a brute-force search finds.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.05, 1.05);
  for (int k = 0; k < 2000; ++k) {
    const Point2 q{u(rng), u(rng)};
    const Location walked = LocatePoint(p, out, q, 0);
    const Location brute = LocatePointBruteForce(p, out, q);
    ASSERT_EQ(walked.found(), brute.found()) << q.x << " " << q.y;
    if (brute.where == Where::kInside) {
      EXPECT_EQ(walked.triangle, brute.triangle);
    }
  }
}

TEST(KeptRemeshTest, RandomPointsWithSliversAHoleAndAVoid) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Case c = MakeCase(3000, seed, /*grid=*/false);
    ASSERT_GT(FoldedJunk(c), 0) << "no junk turns over: the test lost its point";
    Triangulation out;
    ASSERT_TRUE(RemeshAroundKept(c.moved, c.mesh, c.keep, &out));
    ExpectValidRemesh(c, out);
  }
}

// A raster's nodes: cocircular everywhere, collinear along every row.
TEST(KeptRemeshTest, GridWithAHoleAndAVoid) {
  const Case c = MakeCase(2500, 4, /*grid=*/true);
  Triangulation out;
  ASSERT_TRUE(RemeshAroundKept(c.moved, c.mesh, c.keep, &out));
  ExpectValidRemesh(c, out);
}

// Nothing kept, or a kept triangle turned over: not this way.
TEST(KeptRemeshTest, RefusesWhatItCannotDo) {
  Case c = MakeCase(500, 6, /*grid=*/false);
  Triangulation out;
  std::vector<uint8_t> none(c.keep.size(), 0);
  EXPECT_FALSE(RemeshAroundKept(c.moved, c.mesh, none, &out));
  int32_t t = 0;
  while (!c.keep[t]) ++t;
  const int32_t* v = &c.mesh.triangles[3 * t];
  // Its corner across the opposite edge (mirrored through the edge's midpoint).
  c.moved[v[0]] = {c.moved[v[1]].x + c.moved[v[2]].x - c.moved[v[0]].x,
                   c.moved[v[1]].y + c.moved[v[2]].y - c.moved[v[0]].y};
  EXPECT_FALSE(RemeshAroundKept(c.moved, c.mesh, c.keep, &out));
}

}  // namespace
}  // namespace surfreg

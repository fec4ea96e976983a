// EuclideanMst against Prim's algorithm on the complete graph (O(n²), the
// definition of the EMST), and the structure of the traversal order.
#include "measure/spanning_tree.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "measure/delaunay.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

double PrimLength(const std::vector<Point2>& points) {
  const std::size_t n = points.size();
  std::vector<double> best(n, std::numeric_limits<double>::infinity());
  std::vector<char> in_tree(n, 0);
  best[0] = 0.0;
  double total = 0.0;
  for (std::size_t step = 0; step < n; ++step) {
    std::size_t u = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (!in_tree[i] && (u == n || best[i] < best[u])) u = i;
    }
    in_tree[u] = 1;
    total += best[u];
    for (std::size_t i = 0; i < n; ++i) {
      const double d = std::hypot(points[i].x - points[u].x, points[i].y - points[u].y);
      if (!in_tree[i] && d < best[i]) best[i] = d;
    }
  }
  return total;
}

void ExpectValidTree(const std::vector<Point2>& points) {
  const Triangulation mesh = Triangulate(points);
  const SpanningTree tree = EuclideanMst(points, mesh);
  ASSERT_EQ(tree.order.size(), points.size());
  std::vector<int> position(points.size(), -1);
  for (std::size_t k = 0; k < tree.order.size(); ++k) {
    ASSERT_EQ(position[tree.order[k]], -1) << "vertex listed twice";
    position[tree.order[k]] = static_cast<int>(k);
  }
  int roots = 0;
  double length = 0.0;
  for (std::size_t v = 0; v < points.size(); ++v) {
    const int32_t p = tree.parent[v];
    if (p < 0) {
      ++roots;
      continue;
    }
    EXPECT_LT(position[p], position[v]) << "parent after child";
    length += std::hypot(points[v].x - points[p].x, points[v].y - points[p].y);
  }
  EXPECT_EQ(roots, 1);
  EXPECT_NEAR(length, tree.total_length, 1e-9 * length);
  EXPECT_NEAR(tree.total_length, PrimLength(points), 1e-9 * length);
}

TEST(SpanningTreeTest, RandomPointsMatchPrim) {
  for (uint64_t seed : {1, 2, 3}) ExpectValidTree(testing::UniformPoints(800, seed));
}

TEST(SpanningTreeTest, RadixSortedEdgesMatchPrim) {
  // Over 4096 edges: the radix sort rather than the comparison sort.
  ExpectValidTree(testing::UniformPoints(3000, 4));
  ExpectValidTree(testing::GridPoints(60, 50));
}

TEST(SpanningTreeTest, SameTreeOnAnyNumberOfThreads) {
  // Large enough for several chunks of triangles and of edges; the grid's
  // equal lengths make the sort's stability matter.
  for (const std::vector<Point2>& points :
       {testing::UniformPoints(300000, 5), testing::GridPoints(600, 600)}) {
    const Triangulation mesh = Triangulate(points);
    const SpanningTree one = EuclideanMst(points, mesh);
    ASSERT_EQ(one.order.size(), points.size());
    for (int threads : {2, 8}) {
      const SpanningTree many = EuclideanMst(points, mesh, Execution{threads});
      EXPECT_EQ(many.order, one.order) << threads << " threads";
      EXPECT_EQ(many.parent, one.parent) << threads << " threads";
      EXPECT_EQ(many.total_length, one.total_length) << threads << " threads";
    }
  }
}

// Large enough for the vertex ranges' own forests first: the tree meets the
// cycle property on every Delaunay edge (no edge outside the tree is
// shorter than the longest tree edge on the path between its ends), which
// makes it a minimum spanning tree of the triangulation and so the EMST.
// Squared lengths compared exactly; grid points tie everywhere.
TEST(SpanningTreeTest, LargeInputsMeetTheCyclePropertyOnEveryEdge) {
  for (const std::vector<Point2>& points :
       {testing::UniformPoints(150000, 6), testing::ClusteredPoints(150000, 20, 0.01, 7),
        testing::GridPoints(400, 400)}) {
    const Triangulation mesh = Triangulate(points);
    const SpanningTree tree = EuclideanMst(points, mesh, Execution{2});
    const std::size_t n = points.size();
    ASSERT_EQ(tree.order.size(), n);
    const auto length2 = [&](int32_t u, int32_t v) {
      const double dx = points[u].x - points[v].x, dy = points[u].y - points[v].y;
      return dx * dx + dy * dy;
    };
    std::vector<int32_t> depth(n, 0);
    int roots = 0;
    for (const int32_t v : tree.order) {  // parents come first
      if (tree.parent[v] < 0) {
        ++roots;
      } else {
        depth[v] = depth[tree.parent[v]] + 1;
      }
    }
    ASSERT_EQ(roots, 1);
    int64_t violations = 0;
    for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
      for (int i = 0; i < 3; ++i) {
        int32_t u = mesh.triangles[3 * t + (i + 1) % 3], v = mesh.triangles[3 * t + (i + 2) % 3];
        const double edge = length2(u, v);
        double longest = 0.0;  // on the tree path from u to v
        while (u != v) {
          if (depth[u] < depth[v]) std::swap(u, v);
          longest = std::max(longest, length2(u, tree.parent[u]));
          u = tree.parent[u];
        }
        violations += edge < longest;
      }
    }
    EXPECT_EQ(violations, 0) << n;
  }
}

TEST(SpanningTreeTest, GridMatchesPrim) {
  // Every edge has one of two lengths: many equal-length ties.
  ExpectValidTree(testing::GridPoints(25, 20));
}

TEST(SpanningTreeTest, ClusteredMatchesPrim) {
  ExpectValidTree(testing::ClusteredPoints(600, 4, 0.02, 9));
}

TEST(SpanningTreeTest, CollinearPlusOne) {
  // The tree of n collinear points and one apex: n - 1 unit edges plus the
  // shortest apex edge.
  const std::vector<Point2> points = testing::CollinearPlusOne(21);
  const SpanningTree tree = EuclideanMst(points, Triangulate(points));
  EXPECT_NEAR(tree.total_length, 20.0 + 1.0, 1e-12);
}

TEST(SpanningTreeTest, DuplicatesAreLeftOut) {
  std::vector<Point2> points = testing::GridPoints(5, 5);
  points.push_back(points[7]);
  points.push_back(points[0]);
  const Triangulation mesh = Triangulate(points);
  const SpanningTree tree = EuclideanMst(points, mesh);
  EXPECT_EQ(tree.order.size(), 25u);
  EXPECT_EQ(tree.parent[25], -1);
  EXPECT_EQ(tree.parent[26], -1);
  EXPECT_NEAR(tree.total_length, 24.0, 1e-12);
}

}  // namespace
}  // namespace surfreg

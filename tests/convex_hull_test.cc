#include "measure/convex_hull.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "measure/predicates.h"

namespace surfreg {
namespace {

// A square with points inside, on its edges (collinear) and repeated: the
// hull is its four corners, counter-clockwise; its area 1, also far from
// the origin.
TEST(ConvexHullTest, SquareWithCollinearInnerAndRepeatedPoints) {
  for (const double offset : {0.0, 1e6}) {
    std::vector<Point2> points = {{0.5, 0.5}, {1, 0}, {0, 0}, {0.5, 0}, {1, 1}, {0, 1},
                                  {0, 0.5},   {1, 1}, {0.2, 0.7}, {0, 0}};
    for (Point2& p : points) p = {p.x + offset, p.y + offset};
    const std::vector<Point2> hull = ConvexHull(points);
    ASSERT_EQ(hull.size(), 4u) << offset;
    for (std::size_t i = 0; i < hull.size(); ++i) {
      EXPECT_GT(Orient2D(hull[i], hull[(i + 1) % 4], hull[(i + 2) % 4]), 0.0) << offset;
    }
    EXPECT_EQ(PolygonArea(hull), 1.0) << offset;
  }
}

TEST(ConvexHullTest, FewerThanThreeDistinctPointsComeBackSorted) {
  EXPECT_TRUE(ConvexHull({}).empty());
  EXPECT_EQ(ConvexHull({{2, 1}, {2, 1}}).size(), 1u);
  const std::vector<Point2> two = ConvexHull({{3, 0}, {1, 2}, {3, 0}});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].x, 1.0);
  EXPECT_EQ(PolygonArea(two), 0.0);
}

// Against brute force on random clouds: every point is inside or on the
// hull, every hull corner is an input point and a strict left turn.
TEST(ConvexHullTest, HoldsEveryPointOfRandomClouds) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 10.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Point2> points(50 + 20 * trial);
    for (Point2& p : points) p = {g(rng), g(rng)};
    const std::vector<Point2> hull = ConvexHull(points);
    ASSERT_GE(hull.size(), 3u);
    const std::size_t n = hull.size();
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_GT(Orient2D(hull[i], hull[(i + 1) % n], hull[(i + 2) % n]), 0.0);
      bool input = false;
      for (const Point2& p : points) input |= p.x == hull[i].x && p.y == hull[i].y;
      EXPECT_TRUE(input);
    }
    for (const Point2& p : points) {
      for (std::size_t i = 0; i < n; ++i) EXPECT_GE(Orient2D(hull[i], hull[(i + 1) % n], p), 0.0);
    }
    EXPECT_GT(PolygonArea(hull), 0.0);
  }
}

}  // namespace
}  // namespace surfreg

// The Delaunay build in slabs (measure/delaunay_slabs.cc): the definition
// checked directly (exact brute force, tests/testing/delaunay_checks.h) on
// inputs cut into many slabs, the same triangles as the one-thread build,
// the same arrays on any number of threads; inputs that do not split fall
// back.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "measure/delaunay.h"
#include "measure/delaunay_internal.h"
#include "tests/testing/delaunay_checks.h"
#include "tests/testing/point_sets.h"

namespace surfreg {
namespace {

using delaunay_internal::TriangulateInSlabs;
using delaunay_internal::TriangulateOneThread;

void ExpectSameArrays(const Triangulation& a, const Triangulation& b, const std::string& what) {
  EXPECT_EQ(a.triangles, b.triangles) << what;
  EXPECT_EQ(a.neighbors, b.neighbors) << what;
  EXPECT_EQ(a.vertex_triangle, b.vertex_triangle) << what;
  EXPECT_EQ(a.vertex_of_input, b.vertex_of_input) << what;
  EXPECT_EQ(a.num_duplicates, b.num_duplicates) << what;
}

// Builds in slabs (required to split) on `threads`: a perturbed Delaunay
// triangulation with the one-thread build's triangles, and the same arrays
// as on one thread.
void ExpectSlabsMatch(const std::vector<Point2>& points, const std::string& what, int threads,
                      int64_t slab_points) {
  DelaunayOptions options;
  options.execution = Execution{threads};
  Triangulation slabs;
  ASSERT_TRUE(TriangulateInSlabs(points, options, &slabs, slab_points)) << what;
  EXPECT_TRUE(testing::IsPerturbedDelaunay(points, slabs)) << what;
  const Triangulation one = TriangulateOneThread(points, DelaunayOptions());
  EXPECT_EQ(testing::CoordinateTriangles(points, slabs), testing::CoordinateTriangles(points, one))
      << what;
  EXPECT_EQ(slabs.vertex_of_input, one.vertex_of_input) << what;
  Triangulation serial;
  ASSERT_TRUE(TriangulateInSlabs(points, DelaunayOptions(), &serial, slab_points)) << what;
  ExpectSameArrays(slabs, serial, what + " (one thread against " + std::to_string(threads) + ")");
}

TEST(DelaunaySlabsTest, UniformPointsInManySlabs) {
  for (uint64_t seed : {1, 2, 3}) {
    const std::vector<Point2> points = testing::UniformPoints(6000, seed);
    for (int threads : {2, 3, 8, 32}) {
      ExpectSlabsMatch(
          points, "uniform seed " + std::to_string(seed) + " threads " + std::to_string(threads),
          threads, 50);
    }
  }
}

TEST(DelaunaySlabsTest, GridsWhoseCellsAreCocircular) {
  // Slab edges run along grid columns: every seam cell is a tie. (A slab
  // needs two columns: one alone is collinear.)
  ExpectSlabsMatch(testing::GridPoints(90, 70), "grid 90x70", 8, 700);
  ExpectSlabsMatch(testing::GridPoints(40, 300, 0.5, 1e5, -3e3), "tall grid far from the origin", 8,
                   2000);
  ExpectSlabsMatch(testing::GridPoints(300, 8), "wide flat grid", 16, 60);
  ExpectSlabsMatch(testing::RotatedGridPoints(80, 80, 30.0), "grid turned by 30 degrees", 8, 100);
  ExpectSlabsMatch(testing::JitteredGridPoints(90, 90, 0.3, 4), "jittered grid", 8, 100);
}

TEST(DelaunaySlabsTest, ClustersCirclesAndDuplicates) {
  ExpectSlabsMatch(testing::ClusteredPoints(8000, 12, 0.01, 5), "clusters", 8, 100);
  // Repeated points stay in one slab (slabs share no x): the lowest index is kept.
  std::vector<Point2> points = testing::UniformPoints(5000, 9);
  for (int k = 0; k < 2000; ++k) points.push_back(points[(k * 7919) % 5000]);
  ExpectSlabsMatch(points, "duplicates", 8, 100);
  // A point set with many shared x (columns of scattered y).
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point2> columns;
  for (int c = 0; c < 60; ++c) {
    for (int k = 0; k < 100; ++k) columns.push_back({c * 0.25, u(rng)});
  }
  ExpectSlabsMatch(columns, "columns", 8, 500);
}

TEST(DelaunaySlabsTest, LargeInputThroughTriangulateIsTheSameOnAnyThreads) {
  const std::vector<Point2> points = testing::UniformPoints(250000, 21);
  const Triangulation reference = Triangulate(points, DelaunayOptions());
  Triangulation slabs;
  ASSERT_TRUE(TriangulateInSlabs(points, DelaunayOptions(), &slabs));  // large enough by default
  ExpectSameArrays(slabs, reference, "Triangulate builds large inputs in slabs");
  EXPECT_EQ(testing::CoordinateTriangles(points, reference),
            testing::CoordinateTriangles(points, TriangulateOneThread(points, DelaunayOptions())));
  for (int threads : {2, 8}) {
    DelaunayOptions options;
    options.execution = Execution{threads};
    ExpectSameArrays(Triangulate(points, options), reference, "threads " + std::to_string(threads));
  }
}

TEST(DelaunaySlabsTest, InputsThatDoNotSplitFallBack) {
  DelaunayOptions options;
  options.execution = Execution{8};
  Triangulation out;
  // Too small for two slabs of the given size.
  EXPECT_FALSE(TriangulateInSlabs(testing::UniformPoints(150, 1), options, &out, 100));
  // Two columns: each slab would be collinear.
  std::vector<Point2> two_columns;
  for (int k = 0; k < 400; ++k) two_columns.push_back({static_cast<double>(k % 2), k * 0.01});
  EXPECT_FALSE(TriangulateInSlabs(two_columns, options, &out, 50));
  EXPECT_TRUE(out.triangles.empty());
  // Points on a circle: no triangle is final (every circle is the circle).
  EXPECT_FALSE(TriangulateInSlabs(testing::CirclePoints(3000), options, &out, 100));
  // One x for all: no split at all. Triangulate still answers (one thread).
  std::vector<Point2> collinear_then_one = testing::CollinearPlusOne(500);
  EXPECT_FALSE(TriangulateInSlabs(collinear_then_one, options, &out, 50));
  const Triangulation built = Triangulate(two_columns, options);
  ExpectSameArrays(built, TriangulateOneThread(two_columns, DelaunayOptions()), "two columns");
  EXPECT_TRUE(testing::IsPerturbedDelaunay(two_columns, built));
}

}  // namespace
}  // namespace surfreg

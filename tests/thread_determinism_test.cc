// Results do not depend on the number of threads: the parallel stages split
// their work in a fixed way and reduce in a fixed order, so a measure and an
// alignment are bit-identical on 1, 2 and 8 threads (a user's rerun on
// another machine gives the same numbers).
#include <array>
#include <cstring>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "measure/measures.h"
#include "measure/surface.h"
#include "registration/align.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Large enough for every parallel split to run (pair_state.cc splits the
// location at 20000 points).
struct Pair {
  Surface a, b;
};

Pair TerrainPair() {
  const auto dense = testing::SampleUniform(testing::SmoothTerrain, 16000, 0, 100, 0, 100, 71);
  const auto sparse = testing::SampleUniform(testing::SmoothTerrain, 12000, 0, 100, 0, 100, 72);
  const Eigen::Matrix4d truth = testing::TrueMotion({1, -2, 0.5}, 1.5, {1.2, -0.8, 0.3}, testing::Centroid(sparse));
  return {MakeSurface(dense, {}, "a"), MakeSurface(testing::MoveByInverse(sparse, truth), {}, "b")};
}

TEST(MeasureThreads, IsTheSameOnOneTwoThreeAndEightThreads) {
  const Pair pair = TerrainPair();
  MeasureOptions serial;
  serial.threads = 1;
  const MeasureSummary s = Measure(pair.a, pair.b, serial);
  EXPECT_GT(s.rho_d, 0);
  for (const int threads : {2, 3, 8}) {
    SCOPED_TRACE(threads);
    MeasureOptions parallel;
    parallel.threads = threads;
    const MeasureSummary p = Measure(pair.a, pair.b, parallel);
    EXPECT_TRUE(SameBits(s.rho_d, p.rho_d)) << s.rho_d << " " << p.rho_d;
    EXPECT_TRUE(SameBits(s.rho_d_axial, p.rho_d_axial));
    EXPECT_TRUE(SameBits(s.overlap_area, p.overlap_area));
    EXPECT_TRUE(SameBits(s.signed_volume, p.signed_volume));
    EXPECT_TRUE(SameBits(s.volume_above, p.volume_above));
    EXPECT_TRUE(SameBits(s.volume_below, p.volume_below));
    EXPECT_EQ(s.n_cells, p.n_cells);
    EXPECT_EQ(s.n_overlap_nodes, p.n_overlap_nodes);
  }
}

class AlignThreads : public ::testing::TestWithParam<CostKind> {};

TEST_P(AlignThreads, IsTheSameOnOneTwoAndEightThreads) {
  const Pair pair = TerrainPair();
  std::vector<AlignResult> results;
  for (const int threads : {1, 2, 8}) {
    AlignOptions options;
    options.cost = GetParam();
    options.num_threads = threads;
    results.push_back(Align(pair.a, pair.b, options));
  }
  ASSERT_EQ(results[0].verdict, Verdict::kConvergedImproved);
  for (std::size_t k = 1; k < results.size(); ++k) {
    SCOPED_TRACE(k == 1 ? "2 threads" : "8 threads");
    EXPECT_EQ(results[k].verdict, results[0].verdict);
    EXPECT_EQ(results[k].iterations, results[0].iterations);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        EXPECT_TRUE(SameBits(results[k].matrix(i, j), results[0].matrix(i, j)))
            << i << "," << j << ": " << results[k].matrix(i, j) << " vs " << results[0].matrix(i, j);
      }
    }
    for (int i = 0; i < 6; ++i) EXPECT_TRUE(SameBits(results[k].stddev[i], results[0].stddev[i])) << i;
    EXPECT_TRUE(SameBits(results[k].after.rho_d, results[0].after.rho_d));
    // Every solver iteration's cost and gradient: the axial solve's are
    // Ceres' sums over its residual blocks, which on several Ceres threads
    // are added per thread (and differed in their last bits).
    ASSERT_EQ(results[k].log.size(), results[0].log.size());
    for (std::size_t i = 0; i < results[0].log.size(); ++i) {
      EXPECT_TRUE(SameBits(results[k].log[i].cost, results[0].log[i].cost))
          << results[0].log[i].cost_name << " iteration " << i << ": " << results[k].log[i].cost << " vs "
          << results[0].log[i].cost;
      EXPECT_TRUE(SameBits(results[k].log[i].gradient_norm, results[0].log[i].gradient_norm)) << i;
    }
  }
}

// The volume cost (the default here: equal densities), the axial cost, and
// the axial cost at the sparser surface's nodes.
INSTANTIATE_TEST_SUITE_P(Costs, AlignThreads,
                         ::testing::Values(CostKind::kAuto, CostKind::kAxial, CostKind::kAxialSparser));

}  // namespace
}  // namespace surfreg

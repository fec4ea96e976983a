// The held-out check (registration/holdout.h): which samples are held out,
// and whether an alignment improved the part of the reference it did not fit.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include <Eigen/Geometry>

#include "registration/align.h"
#include "registration/holdout.h"
#include "tests/testing/surface_pairs.h"

namespace surfreg {
namespace {

using Points = std::vector<std::array<double, 3>>;

// The tile (i, j) of an xy in the 8 x 8 grid over [0, 100]² (the samples
// span it to within a spacing, so the tiles are these up to the edges).
int TileOf(double x, double y, double x0, double x1, double y0, double y1) {
  const int i = std::min(7, static_cast<int>((x - x0) / ((x1 - x0) / 8)));
  const int j = std::min(7, static_cast<int>((y - y0) / ((y1 - y0) / 8)));
  return j * 8 + i;
}

TEST(HoldoutTest, WholeSeededTilesAreHeldOut) {
  const Points a = testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 3);
  const Surface s = MakeSurface(a, {}, "a");
  const std::vector<uint8_t> held = HeldOutSamples(s, 0.2, 7);
  ASSERT_EQ(held.size(), s.size());
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : a) x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
  // Every tile is wholly in or out; 13 of the 64 tiles (round(0.2 x 64)) are in.
  std::vector<int> in(64, 0), out(64, 0);
  for (std::size_t i = 0; i < a.size(); ++i) ++(held[i] ? in : out)[TileOf(a[i][0], a[i][1], x0, x1, y0, y1)];
  int tiles = 0;
  for (int k = 0; k < 64; ++k) {
    EXPECT_TRUE(in[k] == 0 || out[k] == 0) << "tile " << k << " is split";
    tiles += in[k] > 0;
  }
  EXPECT_EQ(tiles, 13);
  // The same seed gives the same tiles; another seed others.
  EXPECT_EQ(HeldOutSamples(s, 0.2, 7), held);
  EXPECT_NE(HeldOutSamples(s, 0.2, 8), held);
  // Nothing is held out at 0, and never every tile.
  const std::vector<uint8_t> none = HeldOutSamples(s, 0.0, 7);
  EXPECT_EQ(std::count(none.begin(), none.end(), uint8_t{1}), 0);
  const std::vector<uint8_t> most = HeldOutSamples(s, 0.999, 7);
  EXPECT_LT(std::count(most.begin(), most.end(), uint8_t{1}), static_cast<long>(s.size()));
  const Surface fit = WithoutSamples(s, held);
  EXPECT_EQ(fit.size() + std::count(held.begin(), held.end(), uint8_t{1}), s.size());
}

// A known motion: the fit on 80% of the reference also brings the held-out
// 20% into place.
TEST(HoldoutTest, AGoodFitImprovesTheHeldOutPart) {
  const Points a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 31);
  const Points b = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 32);
  const Eigen::Vector3d centre = testing::Centroid(b);
  const Eigen::Matrix4d truth = testing::TrueMotion({1, -2, 0.5}, 2.0, {2.5, -1.5, 0.8}, centre);
  AlignOptions options;
  options.holdout_fraction = 0.2;
  options.holdout_verdict = true;
  const AlignResult r =
      Align(MakeSurface(a, {}, "a"), MakeSurface(testing::MoveByInverse(b, truth), {}, "b"), options);
  ASSERT_TRUE(r.holdout.done);
  EXPECT_GT(r.holdout.samples, 600);
  EXPECT_TRUE(r.holdout.improved);
  EXPECT_EQ(r.verdict, Verdict::kConvergedImproved) << r.verdict_reason;
  EXPECT_LT(r.holdout.after.nmad, 0.2 * r.holdout.before.nmad);
  EXPECT_LT(r.holdout.robust_after, 0.1 * r.holdout.robust_before);
  const testing::MotionError error = testing::CompareMotions(r.matrix, truth, testing::Centroid(testing::MoveByInverse(b, truth)));
  EXPECT_LT(error.rotation_deg, 0.05);
}

// The moving surface lies on the reference in the held-out tiles but 2 m
// above it everywhere else: the fit (which sees only the rest) lowers it by
// 2 m, which the held-out part shows as no improvement, and the verdict says so.
TEST(HoldoutTest, AFitThatOnlySuitsTheFittedPartIsCaught) {
  const Points a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 41);
  Points b = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 42);
  const Surface reference = MakeSurface(a, {}, "a");
  AlignOptions options;
  options.holdout_fraction = 0.25;
  options.holdout_seed = 5;
  const std::vector<uint8_t> held = HeldOutSamples(reference, options.holdout_fraction, options.holdout_seed);
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : a) x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
  std::set<int> held_tiles;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (held[i]) held_tiles.insert(TileOf(a[i][0], a[i][1], x0, x1, y0, y1));
  }
  for (auto& p : b) {
    if (!held_tiles.count(TileOf(p[0], p[1], x0, x1, y0, y1))) p[2] += 2.0;
  }
  const Surface moving = MakeSurface(b, {}, "b");
  for (bool verdict : {false, true}) {
    options.holdout_verdict = verdict;
    const AlignResult r = Align(reference, moving, options);
    ASSERT_TRUE(r.holdout.done);
    EXPECT_NEAR(r.translation[2], -2.0, 0.05);
    EXPECT_FALSE(r.holdout.improved);
    EXPECT_NEAR(r.holdout.after.median, -2.0, 0.1);
    EXPECT_LT(std::fabs(r.holdout.before.median), 0.1);
    if (verdict) {
      EXPECT_EQ(r.verdict, Verdict::kConvergedNotImproved);
      EXPECT_NE(r.verdict_reason.find("held-out"), std::string::npos) << r.verdict_reason;
    } else {
      EXPECT_EQ(r.verdict, Verdict::kConvergedImproved) << r.verdict_reason;
    }
  }
}

}  // namespace
}  // namespace surfreg

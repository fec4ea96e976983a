#include "registration/align.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "measure/input_error.h"
#include "measure/weights.h"
#include "registration/pair_state.h"
#include "registration/volume_cost/volume_cost.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

using testing::CompareMotions;
using testing::MotionError;

struct Pair {
  Surface reference, moving;
  Eigen::Matrix4d truth;
  Eigen::Vector3d moving_centroid;
  double spacing = 1;
};

// Reference = `sample_a`; moving = `sample_b` moved by the inverse of a
// known motion about `axis` by `angle_deg` and `shift` spacings.
Pair MakePair(const std::vector<std::array<double, 3>>& sample_a,
              const std::vector<std::array<double, 3>>& sample_b, const Eigen::Vector3d& axis,
              double angle_deg, const Eigen::Vector3d& shift_spacings, double spacing) {
  Pair pair;
  pair.spacing = spacing;
  const Eigen::Vector3d centre = testing::Centroid(sample_b);
  pair.truth = testing::TrueMotion(axis, angle_deg, shift_spacings * spacing, centre);
  const auto moved = testing::MoveByInverse(sample_b, pair.truth);
  pair.moving_centroid = testing::Centroid(moved);
  pair.reference = MakeSurface(sample_a, {}, "reference");
  pair.moving = MakeSurface(moved, {}, "moving");
  return pair;
}

MotionError AlignAndCompare(const Pair& pair, const AlignOptions& options, AlignResult* out = nullptr) {
  const AlignResult result = Align(pair.reference, pair.moving, options);
  MotionError error = CompareMotions(result.matrix, pair.truth, pair.moving_centroid);
  error.translation /= pair.spacing;
  if (out != nullptr) *out = result;
  return error;
}

const Eigen::Vector3d kAxes[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, -2, 0.5}};

// A cloud moved onto a copy of itself: the minimum is exact at the truth.
TEST(AlignTest, SelfCopyAxialRecoversExactly) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 1);
  for (const Eigen::Vector3d& axis : kAxes) {
    const Pair pair = MakePair(a, a, axis, 5.0, {10, -7, 3}, 100.0 / std::sqrt(6000.0));
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, AlignOptions(), &result);
    EXPECT_LT(error.rotation_deg * M_PI / 180.0, 1e-8) << axis.transpose();
    EXPECT_LT(error.translation, 1e-8) << axis.transpose();
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
    EXPECT_LT(result.after.rho_d_axial, 1e-9);
  }
}

TEST(AlignTest, SelfCopyVolumeRecoversExactly) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 3);
  for (const Eigen::Vector3d& axis : {kAxes[0], kAxes[3]}) {
    const Pair pair = MakePair(a, a, axis, -5.0, {-6, 8, -2}, 100.0 / std::sqrt(5000.0));
    AlignOptions options;
    options.cost = CostKind::kVolume;
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, options, &result);
    EXPECT_LT(error.rotation_deg * M_PI / 180.0, 1e-8) << axis.transpose();
    EXPECT_LT(error.translation, 1e-8) << axis.transpose();
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  }
}

// Two independent samplings of one smooth surface, default options.
TEST(AlignTest, TwoSamplingsOfAnalyticSurface) {
  const double spacing = 100.0 / std::sqrt(6000.0);
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 5);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 6);
  const struct {
    Eigen::Vector3d axis;
    double angle;
    Eigen::Vector3d shift;
  } cases[] = {{kAxes[0], 5.0, {10, -7, 3}},
               {kAxes[1], -4.0, {-3, 10, -5}},
               {kAxes[2], 5.0, {7, 7, 1}},
               {kAxes[3], -5.0, {0, -10, 10}}};
  for (const auto& c : cases) {
    const Pair pair = MakePair(a, b, c.axis, c.angle, c.shift, spacing);
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, AlignOptions(), &result);
    EXPECT_LT(error.rotation_deg, 0.01) << c.axis.transpose();
    EXPECT_LT(error.translation, 0.02) << c.axis.transpose();
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
    EXPECT_LT(result.after.mean_abs_dz, result.before.mean_abs_dz);
    EXPECT_GT(result.overlap_fraction_after, result.overlap_fraction_before);
  }
}

// The axial cost alone: faster, but biased by the interpolation error at the
// nodes, most of all where the surface is steep or a sliver's interpolant is:
// a few such gaps dominate plain vertical least squares. Weighting each gap
// by cos(slope) (the default) shrinks the bias and lets Levenberg–Marquardt
// converge in a few iterations.
TEST(AlignTest, AxialCostAloneOnTwoSamplings) {
  const double spacing = 100.0 / std::sqrt(6000.0);
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 5);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 6);
  const Pair pair = MakePair(a, b, kAxes[3], 5.0, {10, -7, 3}, spacing);
  for (const bool normal : {true, false}) {
    AlignOptions options;
    options.cost = CostKind::kAxial;
    options.normal_distance = normal;
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, options, &result);
    if (normal) {  // measured 0.0025°, 0.0036 spacing, 7 iterations
      EXPECT_LT(error.rotation_deg, 0.01);
      EXPECT_LT(error.translation, 0.02);
      EXPECT_LE(result.iterations, 10);
    } else {  // measured 0.010°, 0.027 spacing, 11 iterations
      EXPECT_LT(error.rotation_deg, 0.15);
      EXPECT_LT(error.translation, 0.1);
    }
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  }
}

// Half of B off A's hull and a large vertical offset: the first
// Levenberg–Marquardt step used to slide B off A entirely, where no node has
// a residual and the cost is 0, and stop there. Such steps are now refused.
TEST(AlignTest, LargeOffsetWithHalfOverlapDoesNotSlideApart) {
  const double spacing = 100.0 / std::sqrt(6000.0);
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 5);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, 6000, 50, 150, 0, 100, 6);
  const Pair pair = MakePair(a, b, kAxes[3], 2.0, {3, -2, 200}, spacing);
  for (const CostKind cost : {CostKind::kAxial, CostKind::kVolume}) {
    AlignOptions options;
    options.cost = cost;
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, options, &result);
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
    EXPECT_GT(result.overlap_fraction_after, 0.4);
    EXPECT_LT(error.rotation_deg, 0.05);
    EXPECT_LT(error.translation, 0.1);
  }
}

// Two irregular samplings of a real DEM (Maunga Whau, 10 m grid, bilinear).
TEST(AlignTest, TwoSamplingsOfRealDem) {
  const testing::GridDem dem = testing::ReadGridDem("configs/data/volcano.xyz");
  ASSERT_EQ(dem.nx * dem.ny, 5307);
  const int n = 5000;
  const double spacing = std::sqrt((dem.x1() - dem.x0) * (dem.y1() - dem.y0) / n);
  const auto a = testing::SampleUniform(std::cref(dem), n, dem.x0, dem.x1(), dem.y0, dem.y1(), 7);
  const auto b = testing::SampleUniform(std::cref(dem), n, dem.x0, dem.x1(), dem.y0, dem.y1(), 8);
  for (const Eigen::Vector3d& axis : {kAxes[0], kAxes[2], kAxes[3]}) {
    const Pair pair = MakePair(a, b, axis, 5.0, {-10, 4, 6}, spacing);
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, AlignOptions(), &result);
    EXPECT_LT(error.rotation_deg, 0.02) << axis.transpose();
    EXPECT_LT(error.translation, 0.05) << axis.transpose();
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  }
}

// A start 20° and 40 spacings away is beyond the prealignment's basin; the
// wide search (50 coarse starts) brings it back.
TEST(AlignTest, WideSearchRecoversAFarStart) {
  const testing::GridDem dem = testing::ReadGridDem("configs/data/volcano.xyz");
  const int n = 2500;
  const double spacing = std::sqrt((dem.x1() - dem.x0) * (dem.y1() - dem.y0) / n);
  const auto a = testing::SampleUniform(std::cref(dem), n, dem.x0, dem.x1(), dem.y0, dem.y1(), 7);
  const auto b = testing::SampleUniform(std::cref(dem), n, dem.x0, dem.x1(), dem.y0, dem.y1(), 8);
  const Pair pair = MakePair(a, b, kAxes[3], 20.0, Eigen::Vector3d(30, -25, 5) / std::sqrt(30 * 30 + 25 * 25 + 25.0) * 40,
                             spacing);
  AlignOptions options;
  // The unweighted volume cost: from this start it ends in the wrong
  // minimum this test needs (with the gap weights it leaves the overlap,
  // a failure that wide_search auto also catches, but not the case here).
  options.gap_weight = 0;
  options.wide_search = AlignOptions::WideSearch::kNever;
  AlignResult stuck;
  const MotionError without = AlignAndCompare(pair, options, &stuck);
  EXPECT_GT(without.rotation_deg, 1.0) << "the start is within the basin: the test lost its point";
  // A wrong minimum that looks like success: the solver converged and the
  // cost went down, but the surfaces lie far apart for two samplings of one
  // terrain, which is what wide_search auto looks at.
  EXPECT_EQ(stuck.verdict, Verdict::kConvergedImproved) << stuck.verdict_reason;
  EXPECT_GT(stuck.after.mean_abs_dz, stuck.sampling_gap);
  for (const auto mode : {AlignOptions::WideSearch::kAlways, AlignOptions::WideSearch::kAuto}) {
    options.wide_search = mode;
    std::vector<std::string> stages;
    options.on_stage = [&stages](const char* stage, double) { stages.emplace_back(stage); };
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, options, &result);
    int announced = 0;  // with auto, the second solve is announced
    for (const std::string& stage : stages) announced += stage.rfind("wide search", 0) == 0;
    EXPECT_EQ(announced, mode == AlignOptions::WideSearch::kAuto ? 1 : 0);
    std::printf("wide search (%s) from 20° / 40 spacings: %.2g deg, %.2g spacings, %.2f s; "
                "mean gap %.3g, sampling gap %.3g\n",
                mode == AlignOptions::WideSearch::kAuto ? "auto" : "always", error.rotation_deg,
                error.translation, result.seconds, result.after.mean_abs_dz, result.sampling_gap);
    EXPECT_LT(error.rotation_deg, 0.05);
    EXPECT_LT(error.translation, 0.1);
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
    EXPECT_LT(result.after.mean_abs_dz, 0.5 * result.sampling_gap);
  }
}

// A start already at the minimum (a previous run's result, e.g. from
// initial_transform) does not improve the measure, but its surfaces lie as
// close as two samplings do: wide_search auto does not search (it took the
// volcano example from 0.3 s to 2.8 s), and the motion stays as good.
TEST(AlignTest, StartAtTheMinimumRunsNoWideSearch) {
  const testing::GridDem dem = testing::ReadGridDem("configs/data/volcano.xyz");
  const int n = 2500;
  const double spacing = std::sqrt((dem.x1() - dem.x0) * (dem.y1() - dem.y0) / n);
  const auto a = testing::SampleUniform(std::cref(dem), n, dem.x0, dem.x1(), dem.y0, dem.y1(), 7);
  const auto b = testing::SampleUniform(std::cref(dem), n, dem.x0, dem.x1(), dem.y0, dem.y1(), 8);
  const Pair pair = MakePair(a, b, kAxes[3], 2.0, Eigen::Vector3d(3, -2, 1), spacing);
  AlignResult first;
  const MotionError from_offset = AlignAndCompare(pair, AlignOptions(), &first);
  ASSERT_EQ(first.verdict, Verdict::kConvergedImproved) << first.verdict_reason;
  EXPECT_FALSE(first.wide_search_ran);
  // Runs from the previous run's result, in turn: a converged solve ends a
  // hair above or below its start, so some keep the start ("not improved").
  AlignResult previous = first;
  int kept = 0;
  for (int run = 0; run < 4; ++run) {
    AlignOptions again;
    again.initial_rotation = previous.rotation_vector;
    again.initial_translation = previous.translation;
    AlignResult next;
    const MotionError error = AlignAndCompare(pair, again, &next);
    std::printf("from the solution: %s, %.2g deg, %.2g spacings (first run %.2g deg, %.2g)\n",
                VerdictName(next.verdict), error.rotation_deg, error.translation,
                from_offset.rotation_deg, from_offset.translation);
    EXPECT_FALSE(next.wide_search_ran) << VerdictName(next.verdict) << ": " << next.verdict_reason;
    EXPECT_NE(next.verdict, Verdict::kFailed) << next.verdict_reason;
    EXPECT_LT(error.rotation_deg, from_offset.rotation_deg + 1e-3);
    EXPECT_LT(error.translation, from_offset.translation + 1e-3);
    kept += next.verdict == Verdict::kConvergedNotImproved;
    previous = next;
  }
  EXPECT_GT(kept, 0) << "no run kept its start: the test lost its point";
}

// At the right pose two samplings of one surface differ by a fraction of
// their sampling gap, so wide_search auto leaves a good alignment alone.
TEST(AlignTest, SamplingGapBoundsTheGapAtTheRightPose) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 21);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 22);
  const double spacing = 100.0 / std::sqrt(4000.0);
  const Pair pair = MakePair(a, b, kAxes[2], 2.0, {3, -2, 1}, spacing);
  AlignOptions options;
  AlignResult result;
  const MotionError error = AlignAndCompare(pair, options, &result);
  std::printf("sampling gap %.3g, mean gap at the solution %.3g (%.2f of it)\n", result.sampling_gap,
              result.after.mean_abs_dz, result.after.mean_abs_dz / result.sampling_gap);
  EXPECT_LT(error.rotation_deg, 0.01);
  EXPECT_GT(result.sampling_gap, 0.0);
  EXPECT_LT(result.after.mean_abs_dz, 0.5 * result.sampling_gap);
  // Its own definition, by brute force on A: the mean distance from a
  // sample to the least-squares plane through its Delaunay neighbours is
  // positive on a curved surface and 0 on a plane.
  std::vector<std::array<double, 3>> plane_a, plane_b;
  for (const auto& p : a) plane_a.push_back({p[0], p[1], 0.2 * p[0] - 0.1 * p[1] + 3});
  for (const auto& p : b) plane_b.push_back({p[0], p[1], 0.2 * p[0] - 0.1 * p[1] + 3});
  const AlignResult flat = Align(MakeSurface(plane_a, {}, "a"), MakeSurface(plane_b, {}, "b"), options);
  EXPECT_LT(flat.sampling_gap, 1e-9);
}

TEST(AlignTest, CoarseToFineAndMultiStartStillRecover) {
  const double spacing = 100.0 / std::sqrt(6000.0);
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 9);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, 6000, 0, 100, 0, 100, 10);
  const Pair pair = MakePair(a, b, kAxes[3], 4.0, {5, 5, -5}, spacing);
  AlignOptions options;
  options.levels = 3;
  options.multi_start = 2;
  AlignResult result;
  const MotionError error = AlignAndCompare(pair, options, &result);
  EXPECT_LT(error.rotation_deg, 0.01);
  EXPECT_LT(error.translation, 0.02);
  int max_level = 0, max_start = 0;
  for (const auto& entry : result.log) {
    max_level = std::max(max_level, entry.level);
    max_start = std::max(max_start, entry.start);
  }
  EXPECT_EQ(max_level, 2);
  EXPECT_EQ(max_start, 2);
}

// Locked rotation: a pure shift is found and the rotation stays exactly 0.
TEST(AlignTest, TranslationOnly) {
  const double spacing = 100.0 / std::sqrt(5000.0);
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 11);
  const Pair pair = MakePair(a, a, kAxes[2], 0.0, {6, -4, 2}, spacing);
  AlignOptions options;
  options.free = {false, false, false, true, true, true};
  AlignResult result;
  const MotionError error = AlignAndCompare(pair, options, &result);
  EXPECT_LT(error.translation, 1e-8);
  EXPECT_EQ(result.rotation_vector[0], 0.0);
  EXPECT_EQ(result.rotation_vector[1], 0.0);
  EXPECT_EQ(result.rotation_vector[2], 0.0);
  EXPECT_EQ(result.stddev[0], 0.0);
  EXPECT_TRUE(result.constrained[0]);
}

// A plane determines tilt and height but not a horizontal shift or a
// rotation about its normal: the verdict says so instead of "converged".
TEST(AlignTest, FlatSurfaceIsIllConditioned) {
  // Horizontal, so that the flat directions are exactly tx, ty and rz.
  auto plane = [](double, double) { return 5.0; };
  const auto a = testing::SampleUniform(plane, 3000, 0, 100, 0, 100, 12);
  const auto b = testing::SampleUniform(plane, 3000, 0, 100, 0, 100, 13);
  Pair pair = MakePair(a, b, kAxes[0], 0.0, {0, 0, 3}, 1.0);
  AlignOptions options;
  options.cost = CostKind::kAxial;
  AlignResult result;
  AlignAndCompare(pair, options, &result);
  EXPECT_EQ(result.verdict, Verdict::kIllConditioned) << result.verdict_reason;
  EXPECT_NE(result.verdict_reason.find("tx"), std::string::npos) << result.verdict_reason;
  EXPECT_NE(result.verdict_reason.find("ty"), std::string::npos) << result.verdict_reason;
  EXPECT_NE(result.verdict_reason.find("rz"), std::string::npos) << result.verdict_reason;
  EXPECT_FALSE(result.constrained[3]);
  EXPECT_TRUE(result.constrained[5]);
  EXPECT_LT(result.after.rho_d_axial, 1e-9);  // the height offset is found
}

TEST(AlignTest, InitialMotionThatFoldsIsAnInputError) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 14);
  const Pair pair = MakePair(a, a, kAxes[0], 0.0, {0, 0, 0}, 1.0);
  AlignOptions options;
  options.initial_rotation = {100.0 * M_PI / 180.0, 0.0, 0.0};
  EXPECT_THROW(Align(pair.reference, pair.moving, options), InputError);
}

// Already aligned: nothing to improve, and the verdict must not claim it.
TEST(AlignTest, AlreadyAlignedIsNotImproved) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 15);
  const Pair pair = MakePair(a, a, kAxes[0], 0.0, {0, 0, 0}, 1.0);
  AlignResult result;
  AlignAndCompare(pair, AlignOptions(), &result);
  EXPECT_EQ(result.verdict, Verdict::kConvergedNotImproved) << result.verdict_reason;
  EXPECT_TRUE(result.matrix.isIdentity(0.0));
}

TEST(AlignTest, InvalidOptionsAreInputErrors) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 500, 0, 100, 0, 100, 16);
  const Surface s = MakeSurface(a);
  AlignOptions options;
  options.free = {false, false, false, false, false, false};
  EXPECT_THROW(Align(s, s, options), InputError);
  options = AlignOptions();
  options.trim_fraction = 0.6;
  EXPECT_THROW(Align(s, s, options), InputError);
  options = AlignOptions();
  options.levels = 0;
  EXPECT_THROW(Align(s, s, options), InputError);
}

// Terrain that really changed (a deposit on the moving survey): a mask
// polygon that leaves it out gives the motion of the stable part; without
// it the deposit pulls the fit.
TEST(AlignTest, MaskExcludesChangedRegion) {
  const double spacing = 100.0 / std::sqrt(5000.0);
  auto changed = [](double x, double y) {
    return testing::SmoothTerrain(x, y) + 6.0 * std::exp(-((x - 75) * (x - 75) + (y - 75) * (y - 75)) / 60.0);
  };
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 21);
  const auto b = testing::SampleUniform(changed, 5000, 0, 100, 0, 100, 22);
  const Pair pair = MakePair(a, b, kAxes[3], 3.0, {4, -3, 2}, spacing);
  // The volume cost is an L1 measure: a local change barely moves its
  // minimum, with or without the mask.
  AlignOptions options;
  options.stable.mode = StableOptions::Mode::kAll;  // the mask alone (stable_terrain_test.cc: auto)
  const MotionError volume_unmasked = AlignAndCompare(pair, options);
  const std::vector<std::array<double, 2>> stable = {{0, 0}, {100, 0}, {100, 55}, {55, 55}, {55, 100}, {0, 100}};
  options.weight = WeightMode::kMask;
  options.mask = {stable};
  AlignResult result;
  const MotionError volume_masked = AlignAndCompare(pair, options, &result);
  EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  // The axial cost is least squares: the deposit pulls it unless masked.
  options = AlignOptions();
  options.stable.mode = StableOptions::Mode::kAll;
  options.cost = CostKind::kAxial;
  const MotionError axial_unmasked = AlignAndCompare(pair, options);
  options.weight = WeightMode::kMask;
  options.mask = {stable};
  const MotionError axial_masked = AlignAndCompare(pair, options);
  std::printf("rotation error (deg) volume %.4f masked %.4f, axial %.4f masked %.4f\n",
              volume_unmasked.rotation_deg, volume_masked.rotation_deg, axial_unmasked.rotation_deg,
              axial_masked.rotation_deg);
  for (const MotionError& e : {volume_unmasked, volume_masked}) {
    EXPECT_LT(e.rotation_deg, 0.02);
    EXPECT_LT(e.translation, 0.05);
  }
  EXPECT_LT(volume_masked.rotation_deg, volume_unmasked.rotation_deg);
  EXPECT_GT(axial_unmasked.rotation_deg, 3 * axial_masked.rotation_deg);
  EXPECT_LT(axial_masked.rotation_deg, 0.15);
}

// The same deposit, left out by a hole in a mask of the whole square, or by
// an exclude mask of that hole alone: the axial cost recovers the motion.
TEST(AlignTest, HoledAndExcludeMasksLeaveOutTheDeposit) {
  const double spacing = 100.0 / std::sqrt(5000.0);
  auto changed = [](double x, double y) {
    return testing::SmoothTerrain(x, y) + 6.0 * std::exp(-((x - 75) * (x - 75) + (y - 75) * (y - 75)) / 60.0);
  };
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 21);
  const auto b = testing::SampleUniform(changed, 5000, 0, 100, 0, 100, 22);
  const Pair pair = MakePair(a, b, kAxes[3], 3.0, {4, -3, 2}, spacing);
  const MaskRing hole = {{55, 55}, {95, 55}, {95, 95}, {55, 95}};
  AlignOptions options;
  options.cost = CostKind::kAxial;
  options.weight = WeightMode::kMask;
  options.mask = {{{-1, -1}, {101, -1}, {101, 101}, {-1, 101}}, hole};
  const MotionError holed = AlignAndCompare(pair, options);
  options.mask = {hole};
  options.mask_mode = MaskMode::kExclude;
  const MotionError excluded = AlignAndCompare(pair, options);
  for (const MotionError& e : {holed, excluded}) {
    EXPECT_LT(e.rotation_deg, 0.15);
    EXPECT_LT(e.translation, 0.1);
  }
}

// The same deposit, left out by per-point weights on the reference (0 on
// the changed quarter, 1 elsewhere: what a raster mask gives), also through
// coarse-to-fine levels on a subsample, which must carry the weights.
TEST(AlignTest, PerPointWeightsExcludeChangedRegion) {
  const double spacing = 100.0 / std::sqrt(5000.0);
  auto changed = [](double x, double y) {
    return testing::SmoothTerrain(x, y) + 6.0 * std::exp(-((x - 75) * (x - 75) + (y - 75) * (y - 75)) / 60.0);
  };
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 21);
  const auto b = testing::SampleUniform(changed, 5000, 0, 100, 0, 100, 22);
  Pair pair = MakePair(a, b, kAxes[3], 3.0, {4, -3, 2}, spacing);
  for (const auto& p : a) pair.reference.weight.push_back(p[0] > 55 && p[1] > 55 ? 0.0 : 1.0);
  AlignResult result;
  MotionError errors[3][2];  // [uniform, weighted, weighted coarse-to-fine][volume, axial]
  for (int c = 0; c < 2; ++c) {
    AlignOptions options;
    options.stable.mode = StableOptions::Mode::kAll;  // the weights alone
    options.cost = c == 0 ? CostKind::kVolume : CostKind::kAxial;
    errors[0][c] = AlignAndCompare(pair, options);
    options.weight = WeightMode::kPerPoint;
    errors[1][c] = AlignAndCompare(pair, options, &result);
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
    EXPECT_LT(result.after.weight_integral, 0.85 * result.after.overlap_area);  // μ in the measures
    options.levels = 2;
    options.subsample = 0.5;
    errors[2][c] = AlignAndCompare(pair, options, &result);
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  }
  std::printf("rotation error (deg) volume %.4f weighted %.4f (levels %.4f), axial %.4f weighted %.4f "
              "(levels %.4f)\n", errors[0][0].rotation_deg, errors[1][0].rotation_deg,
              errors[2][0].rotation_deg, errors[0][1].rotation_deg, errors[1][1].rotation_deg,
              errors[2][1].rotation_deg);
  std::printf("translation error (spacings) volume %.4f weighted %.4f (levels %.4f), axial %.4f "
              "weighted %.4f (levels %.4f)\n", errors[0][0].translation, errors[1][0].translation,
              errors[2][0].translation, errors[0][1].translation, errors[1][1].translation,
              errors[2][1].translation);
  EXPECT_LT(errors[1][0].rotation_deg, errors[0][0].rotation_deg);
  EXPECT_GT(errors[0][1].rotation_deg, 3 * errors[1][1].rotation_deg);
  for (int w : {1, 2}) {
    for (int c = 0; c < 2; ++c) {
      EXPECT_LT(errors[w][c].rotation_deg, c == 0 ? 0.02 : 0.15) << w << c;
      EXPECT_LT(errors[w][c].translation, c == 0 ? 0.05 : 0.3) << w << c;
    }
  }
}

TEST(AlignTest, PerPointWeightsNeedWeightsOnTheReference) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 500, 0, 100, 0, 100, 16);
  Surface plain = MakeSurface(a, {}, "plain.xyz"), weighted = plain, zero = plain;
  weighted.weight.assign(a.size(), 1.0);
  zero.weight.assign(a.size(), 0.0);
  AlignOptions options;
  options.weight = WeightMode::kPerPoint;
  auto message = [&](const Surface& reference, const Surface& moving) {
    try {
      Align(reference, moving, options);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Weights on the moving surface only do not count: μ lives on the reference.
  EXPECT_EQ(message(plain, weighted),
            "align: weight per_point needs per-sample weights on the reference, but plain.xyz has none");
  EXPECT_EQ(message(zero, weighted), "align: weight per_point: every weight of plain.xyz is 0");
  EXPECT_EQ(message(weighted, plain), "no error");
}

// The masked volume cost's gradient against central differences: the mask
// is fixed to the reference, so only B's boundary inside it moves.
TEST(AlignTest, MaskedVolumeGradientMatchesDifferences) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 1500, 0, 100, 0, 100, 23);
  const auto b = testing::SampleUniform(testing::SmoothTerrain, 1200, 10, 90, 5, 95, 24);
  const Surface sa = MakeSurface(a), sb = MakeSurface(b);
  const ReferenceSide ref = PrepareReference(sa);
  const MovingSide mov = PrepareMoving(sb, {sb.origin[0] - sa.origin[0], sb.origin[1] - sa.origin[1],
                                            sb.origin[2] - sa.origin[2]});
  // One polygon (A's local frame); and rings in input coordinates: a hole
  // across B's left edge (x = 10) with an island in it, so B's moving
  // boundary is clipped by triangles of both signs.
  const MaskRegion polygon = MakeMaskRegion({{{-30, -40}, {20, -45}, {35, 10}, {-5, 30}, {-40, 0}}},
                                            MaskMode::kInclude, {0, 0});
  const MaskRegion holed = MakeMaskRegion(
      {{{5, 1}, {95, 1}, {95, 99}, {5, 99}}, {{8, 40}, {30, 40}, {30, 60}, {8, 60}},
       {{9, 45}, {20, 45}, {20, 55}, {9, 55}}},
      MaskMode::kInclude, {sa.origin[0], sa.origin[1]});
  for (const MaskRegion* mask : {&polygon, &holed}) {
    SCOPED_TRACE(mask == &polygon ? "one polygon" : "holed");
    PairState state(ref, mov);
    const std::array<double, 6> theta = {0.01, -0.02, 0.05, 1.5, -2.0, 0.3};
    ASSERT_TRUE(state.Update(theta));
    const VolumeCostValue value = EvaluateVolumeCost(state, true, Execution{1}, mask);
    const VolumeCostValue whole = EvaluateVolumeCost(state, false, Execution{1});
    EXPECT_LT(value.area, (mask == &polygon ? 0.9 : 0.99) * whole.area);
    const Eigen::Matrix<double, 6, 1> g = value.PerAreaGradient();
    for (int k = 0; k < 6; ++k) {
      const double h = 1e-6;
      std::array<double, 6> plus = theta, minus = theta;
      plus[k] += h;
      minus[k] -= h;
      ASSERT_TRUE(state.Update(plus));
      const double fp = EvaluateVolumeCost(state, false, Execution{1}, mask).PerArea();
      ASSERT_TRUE(state.Update(minus));
      const double fm = EvaluateVolumeCost(state, false, Execution{1}, mask).PerArea();
      const double scale = k < 3 ? 50.0 : 1.0;  // compare rotations as lengths
      EXPECT_NEAR(g[k] / scale, (fp - fm) / (2 * h) / scale, 1e-5 * g.norm()) << "parameter " << k;
    }
  }
}

TEST(AlignTest, EulerAnglesMatchComposition) {
  const double rx = 0.3, ry = -0.2, rz = 1.1;
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                                .matrix();
  const std::array<double, 3> e = EulerDegrees(r);
  EXPECT_NEAR(e[0], rx * 180 / M_PI, 1e-12);
  EXPECT_NEAR(e[1], ry * 180 / M_PI, 1e-12);
  EXPECT_NEAR(e[2], rz * 180 / M_PI, 1e-12);
}

// Every linear solver of the trust-region step finds the exact minimum of a
// self copy (the step's linear algebra changes, the minimum does not).
TEST(AlignTest, EveryLinearSolverRecoversSelfCopy) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 3000, 0, 100, 0, 100, 21);
  const Pair pair = MakePair(a, a, kAxes[3], 4.0, {6, -5, 2}, 100.0 / std::sqrt(3000.0));
  for (ceres::LinearSolverType solver : {ceres::DENSE_QR, ceres::DENSE_NORMAL_CHOLESKY, ceres::CGNR}) {
    AlignOptions options;
    options.cost = CostKind::kAxial;
    options.axial_solver.linear_solver_type = solver;
    options.compute_covariance = false;
    AlignResult result;
    const MotionError error = AlignAndCompare(pair, options, &result);
    EXPECT_LT(error.rotation_deg, 1e-6) << static_cast<int>(solver);
    EXPECT_LT(error.translation, 1e-6) << static_cast<int>(solver);
    EXPECT_EQ(result.verdict, Verdict::kConvergedImproved) << result.verdict_reason;
  }
}

// Solving on a quarter of the points still recovers a self copy exactly
// (the subset is a self copy too); the centre stays the full cloud's
// centroid, so the motion means the same as without subsampling.
TEST(AlignTest, SubsampleKeepsTheFullCentroid) {
  const auto a = testing::SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 22);
  const Pair pair = MakePair(a, a, kAxes[1], -3.0, {-4, 6, 1}, 100.0 / std::sqrt(4000.0));
  AlignOptions options;
  options.cost = CostKind::kAxial;
  options.subsample = 0.25;
  options.compute_covariance = false;
  AlignResult result;
  const MotionError error = AlignAndCompare(pair, options, &result);
  EXPECT_LT(error.rotation_deg, 1e-6);
  EXPECT_LT(error.translation, 1e-6);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(result.centre[k], pair.moving_centroid[k], 1e-9);
  options.subsample = 0.0;
  EXPECT_THROW(Align(pair.reference, pair.moving, options), InputError);
  options.subsample = 1e-4;  // fewer than 3 points left
  EXPECT_THROW(Align(pair.reference, pair.moving, options), InputError);
}

}  // namespace
}  // namespace surfreg

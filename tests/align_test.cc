#include "registration/align.h"

#include <cmath>

#include <gtest/gtest.h>

#include "measure/input_error.h"
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

}  // namespace
}  // namespace surfreg

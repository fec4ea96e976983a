// Standard deviations of the motion against the empirical spread of the
// estimates under a known noise model: two samplings of one smooth terrain,
// Gaussian z-noise on both, many seeds, a known translation. Calibrated σ
// makes error / σ a standard normal: its RMS over all seeds and parameters
// is 1.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "registration/align.h"
#include "tests/testing/surface_pairs.h"

namespace surfreg {
namespace {

using Points = std::vector<std::array<double, 3>>;

Points Noisy(Points points, double sigma, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (auto& p : points) p[2] += noise(rng);
  return points;
}

// RMS of error / σ over `seeds` alignments and the six parameters, with
// σ from `options`; also each parameter's ratio of the empirical RMS error
// to the RMS σ.
struct Calibration {
  double rms_z = 0;
  std::array<double, 6> ratio{};
};

Calibration Calibrate(const AlignOptions& options, int seeds) {
  const std::array<double, 3> shift = {1.5, -1.0, 0.4};
  std::array<double, 6> error2{}, sigma2{};
  double z2 = 0;
  for (int s = 0; s < seeds; ++s) {
    const Points a = Noisy(testing::SampleUniform(testing::SmoothTerrain, 2500, 0, 100, 0, 100, 100 + s), 0.1, 500 + s);
    Points b = Noisy(testing::SampleUniform(testing::SmoothTerrain, 2500, 0, 100, 0, 100, 300 + s), 0.1, 700 + s);
    for (auto& p : b) {
      for (int k = 0; k < 3; ++k) p[k] -= shift[k];
    }
    const AlignResult r = Align(MakeSurface(a, {}, "a"), MakeSurface(b, {}, "b"), options);
    EXPECT_EQ(r.verdict, Verdict::kConvergedImproved) << r.verdict_reason;
    for (int k = 0; k < 6; ++k) {
      const double error = k < 3 ? r.rotation_vector[k] : r.translation[k - 3] - shift[k - 3];
      error2[k] += error * error;
      sigma2[k] += r.stddev[k] * r.stddev[k];
      z2 += error * error / (r.stddev[k] * r.stddev[k]);
    }
  }
  Calibration c;
  c.rms_z = std::sqrt(z2 / (6.0 * seeds));
  for (int k = 0; k < 6; ++k) c.ratio[k] = std::sqrt(error2[k] / sigma2[k]);
  return c;
}

TEST(StddevCalibrationTest, SigmaMatchesTheSpreadUnderGaussianNoise) {
  AlignOptions options;  // the default: the sandwich estimate
  const Calibration sandwich = Calibrate(options, 24);
  options.stddev_subsamples = 8;
  const Calibration sub = Calibrate(options, 24);
  options.stddev_subsamples = 0;
  options.stddev_method = AlignOptions::StddevMethod::kInformation;
  const Calibration info = Calibrate(options, 24);
  std::printf("RMS error / sigma over 24 seeds x 6 parameters: sandwich %.3f, subsamples %.3f, information %.3f\n",
              sandwich.rms_z, sub.rms_z, info.rms_z);
  for (const auto& [name, c] : {std::pair<const char*, const Calibration&>{"sandwich", sandwich}, {"subsamples", sub}}) {
    std::printf("per parameter (empirical RMS error / RMS sigma), %s:", name);
    for (double r : c.ratio) std::printf(" %.2f", r);
    std::printf("\n");
  }
  EXPECT_GT(sandwich.rms_z, 0.75);
  EXPECT_LT(sandwich.rms_z, 1.25);
  // Block half-samples are cautious here (0.82 without the gap weight, 0.73
  // with it; tx, ty 0.5–0.6): half of the overlap has more than twice the
  // variance (more outline per area). The option errs on the safe side.
  EXPECT_GT(sub.rms_z, 0.6);
  EXPECT_LT(sub.rms_z, 1.25);
}

// The axial cost's sandwich (H = JᵀJ, the spread of Jᵀr over tiles) under
// the same noise model.
TEST(StddevCalibrationTest, AxialSandwichMatchesTheSpread) {
  AlignOptions options;
  options.cost = CostKind::kAxial;
  const Calibration sandwich = Calibrate(options, 24);
  options.stddev_method = AlignOptions::StddevMethod::kInformation;
  const Calibration info = Calibrate(options, 24);
  std::printf("axial cost, RMS error / sigma over 24 seeds x 6 parameters: sandwich %.3f, information %.3f\n",
              sandwich.rms_z, info.rms_z);
  std::printf("per parameter (empirical RMS error / RMS sigma), axial sandwich:");
  for (double r : sandwich.ratio) std::printf(" %.2f", r);
  std::printf("\n");
  EXPECT_GT(sandwich.rms_z, 0.75);
  EXPECT_LT(sandwich.rms_z, 1.25);
}

// The covariance's diagonal is the stddev², it is symmetric, and a locked
// parameter has a zero row and column; for the sandwich and the subsamples.
TEST(StddevCalibrationTest, CovarianceMatchesTheStddev) {
  const Points a = Noisy(testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 1), 0.1, 2);
  Points b = Noisy(testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 3), 0.1, 4);
  for (auto& p : b) p[0] -= 1.0;
  for (int subsamples : {0, 6}) {
    AlignOptions options;  // subsamples 0: the sandwich estimate
    options.stddev_subsamples = subsamples;
    options.free = {true, true, true, true, true, false};  // tz locked
    const AlignResult r = Align(MakeSurface(a, {}, "a"), MakeSurface(b, {}, "b"), options);
    ASSERT_TRUE(r.covariance.allFinite()) << subsamples;
    EXPECT_LT((r.covariance - r.covariance.transpose()).norm(), 1e-12 * r.covariance.norm());
    for (int k = 0; k < 6; ++k) {
      EXPECT_NEAR(std::sqrt(r.covariance(k, k)), r.stddev[k], 1e-12 * (1 + r.stddev[k])) << subsamples << " " << k;
    }
    EXPECT_EQ(r.stddev_source.rfind(subsamples > 0 ? "block half-samples" : "sandwich over ", 0), 0u)
        << r.stddev_source;
    EXPECT_EQ(r.stddev[5], 0.0);
    EXPECT_EQ(r.covariance.row(5).norm() + r.covariance.col(5).norm(), 0.0);
    EXPECT_GT(r.stddev[3], 0.0);
  }
  // Asked for, the information estimate; and it is what the sandwich
  // replaces (the two differ).
  AlignOptions options;
  const AlignResult sandwich = Align(MakeSurface(a, {}, "a"), MakeSurface(b, {}, "b"), options);
  options.stddev_method = AlignOptions::StddevMethod::kInformation;
  const AlignResult info = Align(MakeSurface(a, {}, "a"), MakeSurface(b, {}, "b"), options);
  EXPECT_EQ(info.stddev_source, "information");
  EXPECT_NE(info.stddev[3], sandwich.stddev[3]);
  EXPECT_EQ(info.rotation_vector, sandwich.rotation_vector);  // the motion is the same
}

}  // namespace
}  // namespace surfreg

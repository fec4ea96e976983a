// The ring fits (ring_fit.h: SampleNoise, FitRingQuadratic), the sampling's
// chord tensor and the density correction (chord_bias.h) against closed
// forms, and Align on a face-like pair sampled 4 : 1.
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "measure/surface.h"
#include "registration/align.h"
#include "registration/axial_cost.h"
#include "registration/chord_bias.h"
#include "registration/pair_state.h"
#include "registration/ring_fit.h"
#include "testing/registration_sides.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

std::vector<Eigen::Vector3d> PointsOf(const ReferenceSide& side) {
  std::vector<Eigen::Vector3d> p(side.xy.size());
  for (std::size_t v = 0; v < p.size(); ++v) p[v] = {side.xy[v].x, side.xy[v].y, side.z[v]};
  return p;
}

std::vector<std::array<double, 3>> Scattered(int n, uint64_t seed, double noise,
                                             double (*f)(double, double)) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::normal_distribution<double> e(0.0, noise > 0 ? noise : 1.0);
  std::vector<std::array<double, 3>> points;
  for (int k = 0; k < n; ++k) {
    const double x = u(rng), y = u(rng);
    points.push_back({x, y, f(x, y) + (noise > 0 ? e(rng) : 0.0)});
  }
  return points;
}

double Quadratic(double x, double y) { return 0.3 * x * x - 0.5 * x * y + 0.2 * y * y + x - 2 * y + 1; }
double Plane(double x, double y) { return 0.3 * x - 0.2 * y + 4; }

// A quadratic is fitted exactly at every inner node (H = [[0.6, −0.5],
// [−0.5, 0.4]]) and leaves no noise; a plane with Gaussian noise of σ 0.1
// gives σ back within 10%, and its shrunk curvatures are a small part of
// the unshrunk ones (which are all noise).
TEST(RingFitTest, QuadraticIsExactAndNoiseIsMeasured) {
  const ReferenceSide quadratic = PrepareReference(MakeSurface(Scattered(2000, 3, 0, Quadratic), {}, "q"));
  const std::vector<Eigen::Vector3d> q = PointsOf(quadratic);
  RingQuadratic fit;
  int fitted = 0;
  for (std::size_t v = 0; v < q.size(); ++v) {
    if (!FitRingQuadratic(q, quadratic.mesh, v, 0.0, &fit)) continue;
    ++fitted;
    EXPECT_NEAR(fit.hessian[0], 0.6, 1e-6);  // heights up to 60, spacings 0.2: rounding
    EXPECT_NEAR(fit.hessian[1], -0.5, 1e-6);
    EXPECT_NEAR(fit.hessian[2], 0.4, 1e-6);
  }
  EXPECT_GT(fitted, 1600);  // all but the hull's nodes and some next to it
  EXPECT_LT(SampleNoise(q, quadratic.mesh), 1e-9);

  const ReferenceSide noisy = PrepareReference(MakeSurface(Scattered(6000, 4, 0.1, Plane), {}, "noisy"));
  const std::vector<Eigen::Vector3d> p = PointsOf(noisy);
  const double sigma = SampleNoise(p, noisy.mesh);
  EXPECT_NEAR(sigma, 0.1, 0.01);
  double raw = 0, shrunk = 0;
  for (std::size_t v = 0; v < p.size(); ++v) {
    if (!FitRingQuadratic(p, noisy.mesh, v, 0.0, &fit)) continue;
    raw += fit.hessian.norm();
    ASSERT_TRUE(FitRingQuadratic(p, noisy.mesh, v, sigma, &fit));
    shrunk += fit.hessian.norm();
  }
  std::printf("plane + noise 0.1: sigma %.4f, shrunk / raw curvature %.3f\n", sigma, shrunk / raw);
  EXPECT_LT(shrunk, 0.4 * raw);
}

// An equilateral lattice of spacing h: every triangle is equilateral, so
// the area per point is √3/2 h² and the chord tensor (1/24 Σ eeᵀ = h²/16 I)
// per unit area per point I / (8√3), whatever h.
TEST(ChordBiasTest, SamplingOfAnEquilateralLattice) {
  for (double h : {0.5, 3.0}) {
    std::vector<std::array<double, 3>> lattice;
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) lattice.push_back({h * (i + 0.5 * j), h * j * std::sqrt(3.0) / 2, 0.0});
    const ReferenceSide side = PrepareReference(MakeSurface(lattice, {}, "lattice"));
    // The data domain: without the slivers that the slanted outline's
    // rounding may leave on the hull.
    const SamplingShape shape = MeasureSampling(PointsOf(side), side.mesh, side.domain);
    EXPECT_NEAR(shape.area_per_point, std::sqrt(3.0) / 2 * h * h, 1e-9 * h * h);
    EXPECT_NEAR(shape.chord(0, 0), 1 / (8 * std::sqrt(3.0)), 1e-9);
    EXPECT_NEAR(shape.chord(1, 1), 1 / (8 * std::sqrt(3.0)), 1e-9);
    EXPECT_NEAR(shape.chord(0, 1), 0.0, 1e-9);
  }
}

double Bowl(double x, double y) { return 0.05 * ((x - 5) * (x - 5) + (y - 5) * (y - 5)); }

// The mean over random points of the two interpolations' difference.
double MeanDifference(const ReferenceSide& a, const MovingSide& b, double* count) {
  const std::vector<Eigen::Vector3d> pa = PointsOf(a);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(2.0, 8.0);
  double sum = 0;
  int n = 0;
  for (int k = 0; k < 400; ++k) {
    const double x = u(rng), y = u(rng);
    double za = 0, zb = 0;
    if (!HeightAt(pa, a.mesh, x, y, &za) || !HeightAt(b.points, b.mesh, x, y, &zb)) continue;
    sum += zb - za;
    ++n;
  }
  *count = n;
  return sum / n;
}

// A bowl sampled at 2000 and at 500 random points (one frame): the sparser
// interpolation lies higher by about tr(H ΔM); after the correction the
// mean difference is a fifth of that or less, and only the sparser side
// moved. Below the ratio, or with 0, nothing changes.
TEST(ChordBiasTest, CorrectsTheSparserSideOfABowl) {
  const Surface dense = MakeSurface(Scattered(2000, 5, 0, Bowl), {}, "dense", 1e9);
  const Surface sparse = MakeSurface(Scattered(500, 6, 0, Bowl), {}, "sparse", 1e9);
  ASSERT_EQ(dense.origin, sparse.origin);  // one frame: no shift
  ReferenceSide a = PrepareReference(dense);
  MovingSide b = PrepareMoving(sparse, {0, 0, 0});
  double n = 0;
  const double before = MeanDifference(a, b, &n);
  ASSERT_GT(n, 300);
  const SamplingShape sa = MeasureSampling(PointsOf(a), a.mesh, a.domain);
  const SamplingShape sb = MeasureSampling(b.points, b.mesh, b.domain);
  const double expected = 0.1 * (sb.area_per_point - sa.area_per_point) * (sa.chord + sb.chord).trace() / 2;
  std::printf("bowl 2000 : 500: mean difference %.5f, tr(H dM) %.5f\n", before, expected);
  EXPECT_NEAR(before, expected, 0.25 * expected);

  const ReferenceSide a0 = a;
  const MovingSide b0 = b;
  DensityCorrection none = CorrectDensityBias(0, &a, &b);
  EXPECT_FALSE(none.applied);
  none = CorrectDensityBias(5.0, &a, &b);  // the ratio is about 4
  EXPECT_FALSE(none.applied);
  EXPECT_NEAR(none.ratio, 4.0, 0.6);
  EXPECT_EQ(a.z, a0.z);
  ASSERT_EQ(b.points.size(), b0.points.size());
  for (std::size_t v = 0; v < b.points.size(); ++v) ASSERT_EQ(b.points[v], b0.points[v]);

  const DensityCorrection done = CorrectDensityBias(1.2, &a, &b);
  EXPECT_TRUE(done.applied);
  EXPECT_GT(done.one_sign_share, 0.95);  // a bowl: curved one way everywhere
  EXPECT_FALSE(done.reference);
  EXPECT_EQ(a.z, a0.z);
  const double after = MeanDifference(a, b, &n);
  std::printf("after the correction: %.5f\n", after);
  EXPECT_LT(std::fabs(after), 0.2 * std::fabs(before));
}

// A face-like cap (align_api_test's) sampled at 4000 and 1000 points, a
// known motion: the vertical error with the correction is a third of that
// without or less, and the report says which side was corrected.
double FaceLike(double x, double y) {
  const double cap = 1.0 - (x / 70) * (x / 70) - (y / 90) * (y / 90);
  return 40.0 * std::sqrt(std::max(0.0, cap)) + 12.0 * std::exp(-(x * x + (y + 5) * (y + 5)) / 120.0);
}

TEST(ChordBiasTest, AlignOfAFacePairSampledFourToOne) {
  const auto dense = testing::SampleUniform(FaceLike, 4000, -45, 45, -55, 55, 31);
  const auto sparse = testing::SampleUniform(FaceLike, 1000, -45, 45, -55, 55, 32);
  const Eigen::Matrix4d truth = testing::TrueMotion({1, -2, 0.5}, 2.0, {1.5, -1.0, 0.3}, testing::Centroid(sparse));
  const Surface a = MakeSurface(dense, {}, "dense");
  const Surface b = MakeSurface(testing::MoveByInverse(sparse, truth), {}, "sparse");
  AlignOptions off;
  off.density_correction = 0;
  const AlignResult plain = Align(a, b, off);
  const AlignResult corrected = Align(a, b);
  ASSERT_EQ(plain.verdict, Verdict::kConvergedImproved);
  ASSERT_EQ(corrected.verdict, Verdict::kConvergedImproved);
  EXPECT_EQ(plain.chord_correction, "none");
  EXPECT_EQ(corrected.chord_correction, "moving");
  // Curved one way: the volume cost stays (the automatic switch is for terrain).
  EXPECT_EQ(corrected.solve_cost, "volume");
  EXPECT_EQ(plain.solve_cost, "volume");
  EXPECT_NEAR(corrected.density_ratio, 4.0, 0.6);
  const Eigen::Vector3d c = testing::Centroid(testing::MoveByInverse(sparse, truth));
  const Eigen::Vector4d centre(c.x(), c.y(), c.z(), 1.0);
  const double error_plain = ((plain.matrix - truth) * centre)[2];
  const double error_corrected = ((corrected.matrix - truth) * centre)[2];
  std::printf("face 4000 : 1000: tz error %.3g without, %.3g with the correction (sigma %.3g)\n", error_plain,
              error_corrected, corrected.stddev[5]);
  EXPECT_GT(std::fabs(error_plain), 3 * corrected.stddev[5]);  // the bias is real
  EXPECT_LT(std::fabs(error_corrected), std::fabs(error_plain) / 3);
}

// Terrain whose curvature changes sign from place to place (hills, a
// valley, a ripple), sampled 4 : 1: the corrections have no dominant sign,
// the chords cancel over the overlap, and nothing is changed.
TEST(ChordBiasTest, MixedCurvatureIsLeftAlone) {
  const Surface dense = MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 41), {}, "dense", 1e9);
  const Surface sparse = MakeSurface(testing::SampleUniform(testing::SmoothTerrain, 1000, 0, 100, 0, 100, 42), {}, "sparse", 1e9);
  ReferenceSide a = PrepareReference(dense);
  MovingSide b = PrepareMoving(sparse, {0, 0, 0});
  const MovingSide b0 = b;
  const DensityCorrection c = CorrectDensityBias(1.2, &a, &b);
  std::printf("terrain 4000 : 1000: ratio %.2f, one-sign share %.3f\n", c.ratio, c.one_sign_share);
  EXPECT_GT(c.ratio, 3.0);
  EXPECT_GT(c.one_sign_share, 0.5);
  EXPECT_LT(c.one_sign_share, kMinOneSignShare);
  EXPECT_FALSE(c.applied);
  for (std::size_t v = 0; v < b.points.size(); ++v) ASSERT_EQ(b.points[v], b0.points[v]);
}

// The axial cost at one surface's nodes only: its residuals are exactly the
// ones it has with both, and the other's are inactive.
TEST(AxialNodesTest, OneSidesNodesAreTheSameResiduals) {
  const auto sides = TerrainSides(1200, 300, 10, 90);
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0.002, -0.001, 0.003, 0.4, -0.3, 0.1}));
  AxialSettings both, reference_only, moving_only;
  reference_only.moving_nodes = false;
  moving_only.reference_nodes = false;
  AxialResiduals r_both, r_reference, r_moving;
  ComputeAxialResiduals(state, both, true, &r_both);
  ComputeAxialResiduals(state, reference_only, true, &r_reference);
  ComputeAxialResiduals(state, moving_only, true, &r_moving);
  const std::size_t na = sides->reference.xy.size();
  ASSERT_EQ(r_both.r.size(), r_reference.r.size());
  int64_t on_a = 0, on_b = 0;
  for (std::size_t k = 0; k < r_both.r.size(); ++k) {
    const bool of_a = k < na;
    EXPECT_EQ(r_reference.active[k], of_a ? r_both.active[k] : 0) << k;
    EXPECT_EQ(r_moving.active[k], of_a ? 0 : r_both.active[k]) << k;
    EXPECT_EQ((of_a ? r_reference : r_moving).r[k], r_both.r[k]) << k;  // unnormalized: the same residual
    on_a += of_a && r_both.active[k];
    on_b += !of_a && r_both.active[k];
  }
  EXPECT_GT(on_a, 600);  // B covers 64% of A
  EXPECT_GT(on_b, 200);
  EXPECT_EQ(r_reference.active_count, on_a);
  EXPECT_EQ(r_moving.active_count, on_b);
}

// Terrain sampled 4000 : 1000 (a known motion): the axial cost at the
// sparser surface's samples, against the denser interpolation, beats it at
// both surfaces' nodes, in rotation and in translation.
TEST(AxialNodesTest, TheSparserSurfacesNodesAlignTerrainOfTwoResolutions) {
  const auto dense = testing::SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 51);
  const auto sparse = testing::SampleUniform(testing::SmoothTerrain, 1000, 0, 100, 0, 100, 52);
  const Eigen::Matrix4d truth = testing::TrueMotion({1, -2, 0.5}, 2.0, {1.5, -1.0, 0.3}, testing::Centroid(sparse));
  const auto moved = testing::MoveByInverse(sparse, truth);
  const Surface a = MakeSurface(dense, {}, "dense");
  const Surface b = MakeSurface(moved, {}, "sparse");
  AlignOptions options;
  options.cost = CostKind::kAxial;
  const AlignResult at_both = Align(a, b, options);
  options.cost = CostKind::kAxialSparser;
  const AlignResult at_sparser = Align(a, b, options);
  ASSERT_EQ(at_both.verdict, Verdict::kConvergedImproved);
  ASSERT_EQ(at_sparser.verdict, Verdict::kConvergedImproved);
  const Eigen::Vector3d c = testing::Centroid(moved);
  const testing::MotionError e_both = testing::CompareMotions(at_both.matrix, truth, c);
  const testing::MotionError e_sparser = testing::CompareMotions(at_sparser.matrix, truth, c);
  std::printf("terrain 4000 : 1000, axial: both %.3g deg / %.3g, sparser %.3g deg / %.3g\n", e_both.rotation_deg,
              e_both.translation, e_sparser.rotation_deg, e_sparser.translation);
  EXPECT_LT(e_sparser.rotation_deg, e_both.rotation_deg);
  EXPECT_LT(e_sparser.translation, e_both.translation);
  EXPECT_EQ(at_sparser.solve_cost, "axial at the sparser surface's nodes");
  EXPECT_EQ(at_both.solve_cost, "axial");

  // The default (cost auto) chooses the same for terrain 4 : 1, mixed
  // curvature: the same motion as asked for explicitly.
  const AlignResult automatic = Align(a, b);
  EXPECT_EQ(automatic.solve_cost, "axial at the sparser surface's nodes");
  EXPECT_GT(automatic.density_ratio, 3.5);
  EXPECT_TRUE((automatic.matrix - at_sparser.matrix).cwiseAbs().maxCoeff() < 1e-12)
      << automatic.matrix << "\n" << at_sparser.matrix;
  // An explicit volume cost is never replaced.
  AlignOptions volume_cost;
  volume_cost.cost = CostKind::kVolume;
  EXPECT_EQ(Align(a, b, volume_cost).solve_cost, "volume");
}

// Below kSparserNodesRatio the automatic choice stays with the volume cost:
// terrain sampled 2 : 1 (below 2.5).
TEST(AxialNodesTest, TerrainCloseInResolutionKeepsTheVolumeCost) {
  const auto dense = testing::SampleUniform(testing::SmoothTerrain, 2000, 0, 100, 0, 100, 53);
  const auto sparse = testing::SampleUniform(testing::SmoothTerrain, 1000, 0, 100, 0, 100, 54);
  const Surface a = MakeSurface(dense, {}, "dense");
  const Surface b = MakeSurface(sparse, {}, "sparse");
  const AlignResult automatic = Align(a, b);
  EXPECT_LT(automatic.density_ratio, kSparserNodesRatio);
  EXPECT_GT(automatic.density_ratio, 1.5);
  EXPECT_EQ(automatic.solve_cost, "volume");
}

TEST(ChordBiasTest, RatiosBelowOneAreRefused) {
  AlignOptions options;
  std::string error;
  options.density_correction = 0.5;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("density_correction"), std::string::npos) << error;
  options.density_correction = 0;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.density_correction = 1;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  // trim_fraction trims the axial residuals: refused with a volume cost.
  options.trim_fraction = 0.1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("trim_fraction"), std::string::npos) << error;
  options.cost = CostKind::kAxialSparser;
  EXPECT_TRUE(options.IsValid(&error)) << error;
}

}  // namespace
}  // namespace surfreg

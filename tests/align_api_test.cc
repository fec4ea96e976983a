// The library's face of Align (registration/align.h): the start as a rigid
// motion, the answer as one (reference_from_moving), and the reports.
// Swapping reference and moving must give the inverse motion within the
// standard deviations Align states, for a terrain pair, a face-like pair
// and a grid DEM against a scattered cloud.
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>
#include <utility>

#include <gtest/gtest.h>

#include "measure/measures.h"
#include "registration/align.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

// A face-like patch: an ellipsoidal cap with a nose and two brows.
double FaceLike(double x, double y) {
  const double cap = 1.0 - (x / 70) * (x / 70) - (y / 90) * (y / 90);
  return 40.0 * std::sqrt(std::max(0.0, cap)) + 12.0 * std::exp(-(x * x + (y + 5) * (y + 5)) / 120.0) +
         4.0 * std::exp(-((x - 20) * (x - 20) + (y - 25) * (y - 25)) / 90.0) +
         4.0 * std::exp(-((x + 20) * (x + 20) + (y - 25) * (y - 25)) / 90.0);
}

std::vector<std::array<double, 3>> Grid(const testing::HeightFunction& f, double x0, double x1, double y0,
                                        double y1, int n) {
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = x0 + (x1 - x0) * i / (n - 1), y = y0 + (y1 - y0) * j / (n - 1);
      points.push_back({x, y, f(x, y)});
    }
  }
  return points;
}

struct Family {
  const char* name;
  std::vector<std::array<double, 3>> a, b;  // two samplings of one surface
};

Family MakeFamily(int k) {
  using testing::SampleUniform;
  switch (k) {
    case 0:
      return {"terrain", SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 21),
              SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 22)};
    case 1:
      return {"face", SampleUniform(FaceLike, 4000, -45, 45, -55, 55, 23),
              SampleUniform(FaceLike, 4000, -45, 45, -55, 55, 24)};
    default:
      return {"grid and cloud", Grid(testing::SmoothTerrain, 0, 100, 0, 100, 64),
              SampleUniform(testing::SmoothTerrain, 4000, 0, 100, 0, 100, 25)};
  }
}

class SwapTest : public ::testing::TestWithParam<int> {};

// Align(a, b) and Align(b, a), each from the identity: the composed motion
// b_from_a · a_from_b is the identity within half of the two runs' σ
// together (per rotation axis; for the translation, at B's centroid, with the
// second run's rotation σ times the lever to its centre). The volume between
// two surfaces is symmetric, and so must be the weights: weights from the
// reference's own interpolation gaps or local spacing made the face's tz
// loop 2–3 σ (RMS over 20 seeds); from its curvature alone, under 0.2 σ.
TEST_P(SwapTest, SwappingTheSurfacesGivesTheInverseWithinHalfTheStatedSigma) {
  const Family family = MakeFamily(GetParam());
  const Eigen::Matrix4d truth = testing::TrueMotion({1, -2, 0.5}, 2.0, {1.5, -1.0, 0.3}, testing::Centroid(family.b));
  const Surface a = MakeSurface(family.a, {}, "a");
  const Surface b = MakeSurface(testing::MoveByInverse(family.b, truth), {}, "b");
  const AlignResult ab = Align(a, b);
  ASSERT_EQ(ab.verdict, Verdict::kConvergedImproved) << family.name << ": " << ab.verdict_reason;
  const AlignResult ba = Align(b, a);
  ASSERT_EQ(ba.verdict, Verdict::kConvergedImproved) << family.name << ": " << ba.verdict_reason;

  const Rigid3d loop = ba.reference_from_moving * ab.reference_from_moving;  // b_from_a · a_from_b
  const Eigen::Vector3d w = loop.RotationVector();
  const Eigen::Vector3d centre_b(ab.centre[0], ab.centre[1], ab.centre[2]);  // B's centroid
  const Eigen::Vector3d centre_a(ba.centre[0], ba.centre[1], ba.centre[2]);
  const double lever = (ab.reference_from_moving * centre_b - centre_a).norm();
  const Eigen::Vector3d shift = loop.ShiftOf(centre_b);
  for (int k = 0; k < 3; ++k) {
    const double sigma_w = std::hypot(ab.stddev[k], ba.stddev[k]);
    const double sigma_t = std::sqrt(ab.stddev[3 + k] * ab.stddev[3 + k] + ba.stddev[3 + k] * ba.stddev[3 + k] +
                                     lever * lever * ba.stddev[k] * ba.stddev[k]);
    ASSERT_GT(sigma_w, 0) << family.name;
    EXPECT_LE(std::fabs(w[k]), 0.5 * sigma_w) << family.name << " rotation " << k;
    EXPECT_LE(std::fabs(shift[k]), 0.5 * sigma_t) << family.name << " translation " << k;
    std::printf("%s, axis %d: |loop| / sigma rotation %.2f, translation %.2f (|shift| %.3g, sigma %.3g)\n",
                family.name, k, std::fabs(w[k]) / sigma_w, std::fabs(shift[k]) / sigma_t, std::fabs(shift[k]), sigma_t);
  }
}

INSTANTIATE_TEST_SUITE_P(Families, SwapTest, ::testing::Values(0, 1, 2));

// The start given as a rigid motion is the same start as the rotation about
// the moving centroid and its shift: the same answer, to rounding.
TEST(AlignApiTest, RigidStartEqualsRotationAndShiftStart) {
  const Family family = MakeFamily(0);
  const Surface a = MakeSurface(family.a, {}, "a");
  const Surface b = MakeSurface(family.b, {}, "b");
  AlignOptions by_theta;
  by_theta.initial_rotation = {0.01, -0.02, 0.015};
  by_theta.initial_translation = {0.5, -0.3, 0.1};
  const Eigen::Vector3d centroid = testing::Centroid(family.b);
  AlignOptions by_rigid;
  by_rigid.initial_reference_from_moving =
      Rigid3d::RotationAbout({0.01, -0.02, 0.015}, centroid, {0.5, -0.3, 0.1});
  const AlignResult r1 = Align(a, b, by_theta), r2 = Align(a, b, by_rigid);
  EXPECT_LT((r1.matrix - r2.matrix).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((r2.reference_from_moving.ToMatrix() - r2.matrix).cwiseAbs().maxCoeff(), 0.0 + 1e-15);
}

TEST(AlignApiTest, BadRigidStartsAreRefused) {
  AlignOptions options;
  std::string error;
  options.initial_reference_from_moving = Rigid3d();
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.initial_rotation = {0.1, 0, 0};
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("both set the start"), std::string::npos) << error;
  options.initial_rotation = {0, 0, 0};
  options.initial_reference_from_moving->rotation(0, 0) = 1.1;  // not a rotation
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("rigid"), std::string::npos) << error;
}

// The solvers' Ceres options are the ones used (a volume solve capped at 2
// iterations per level stops there) and are checked by Ceres' IsValid.
TEST(AlignApiTest, CeresOptionsAreUsedAndChecked) {
  const Family family = MakeFamily(0);
  const Surface a = MakeSurface(family.a, {}, "a");
  const Surface b = MakeSurface(testing::MoveByInverse(family.b, testing::TrueMotion({0, 0, 1}, 1.0, {1, 0, 0},
                                                                                       testing::Centroid(family.b))),
                                {}, "b");
  AlignOptions options;
  options.prealign = false;
  options.wide_search = AlignOptions::WideSearch::kNever;
  options.volume_solver.max_num_iterations = 2;
  const AlignResult capped = Align(a, b, options);
  EXPECT_LE(capped.iterations, 2 * 6);  // at most 2 per round of the volume solve
  options.volume_solver.max_num_iterations = 100;
  EXPECT_GT(Align(a, b, options).iterations, capped.iterations);

  std::string error;
  AlignOptions bad;
  bad.axial_solver.max_trust_region_radius = -1;  // Ceres: must be positive
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_EQ(error.rfind("axial_solver: ", 0), 0u) << error;
  bad = AlignOptions();
  bad.volume_solver.max_lbfgs_rank = 0;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_EQ(error.rfind("volume_solver: ", 0), 0u) << error;
  bad = AlignOptions();
  bad.axial_solver.linear_solver_type = ceres::CGNR;
  bad.axial_solver.trust_region_strategy_type = ceres::DOGLEG;
  EXPECT_FALSE(bad.IsValid(&error));
}

// keep_node_gaps: the measures before and after keep d at every sample of
// each surface, equal to measuring afresh at the initial and final motion;
// without it they keep none (a changed pair too, whose stable terrain is
// found from the first fit's own gaps).
TEST(AlignApiTest, NodeGapsAreKeptOnlyWhenAsked) {
  const Family family = MakeFamily(0);
  const Surface a = MakeSurface(family.a, {}, "a");
  std::vector<std::array<double, 3>> changed = family.b;
  for (auto& p : changed) p[2] += 4.0 * std::exp(-((p[0] - 30) * (p[0] - 30) + (p[1] - 60) * (p[1] - 60)) / 60.0);
  for (const auto& points : {family.b, changed}) {
    const Surface b = MakeSurface(
        testing::MoveByInverse(points, testing::TrueMotion({0, 1, 0}, 0.5, {0.3, 0, 0.2}, testing::Centroid(points))),
        {}, "b");
    const AlignResult plain = Align(a, b);
    EXPECT_TRUE(plain.after.dz_a.empty() && plain.after.dz_b.empty() && plain.before.dz_a.empty());
    AlignOptions options;
    options.keep_node_gaps = true;
    const AlignResult kept = Align(a, b, options);
    ASSERT_EQ(kept.verdict, Verdict::kConvergedImproved) << kept.verdict_reason;
    EXPECT_EQ(kept.matrix, plain.matrix);
    MeasureOptions measure;
    measure.keep_node_gaps = true;
    const MeasureSummary before = Measure(a, b, measure);
    const MeasureSummary after = Measure(a, TransformSurface(b, kept.matrix), measure);
    for (const auto& [got, want] : {std::pair{&kept.before, &before}, std::pair{&kept.after, &after}}) {
      ASSERT_EQ(got->dz_a.size(), a.size());
      ASSERT_EQ(got->dz_b.size(), b.size());
      ASSERT_EQ(got->node_area_a.size(), a.size());
      int finite = 0;
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(std::isfinite(got->dz_a[i]), std::isfinite(want->dz_a[i])) << i;
        if (!std::isfinite(want->dz_a[i])) continue;
        ++finite;
        EXPECT_NEAR(got->dz_a[i], want->dz_a[i], 1e-9) << i;
        EXPECT_NEAR(got->node_area_a[i], want->node_area_a[i], 1e-9) << i;
      }
      EXPECT_GT(finite, static_cast<int>(a.size()) / 2);
    }
  }
}

// FullReport: the CLI's summary lines in order, each ending in a newline;
// BriefReport: one line with the verdict.
TEST(AlignApiTest, ReportsNameEveryItem) {
  const Family family = MakeFamily(0);
  AlignOptions options;
  options.holdout_fraction = 0.2;
  const AlignResult r = Align(MakeSurface(family.a, {}, "a"), MakeSurface(family.b, {}, "b"), options);
  const std::string full = r.FullReport();
  std::istringstream lines(full);
  std::vector<std::string> keys;
  for (std::string line; std::getline(lines, line);) keys.push_back(line.substr(0, line.find(':')));
  const std::vector<std::string> want = {"verdict", "rotation", "euler", "translation", "stddev", "95% interval",
                                         "rho'_d", "mean |dz|", "overlap", "stable", "held out", "              before",
                                         "              after  before", "iterations", "time"};
  ASSERT_EQ(keys.size(), want.size()) << full;
  for (std::size_t k = 0; k < want.size(); ++k) {
    if (want[k].rfind("              ", 0) == 0) continue;  // the held-out statistics lines
    EXPECT_EQ(keys[k], want[k]) << full;
  }
  EXPECT_EQ(full.back(), '\n');
  const std::string brief = r.BriefReport();
  EXPECT_EQ(brief.find('\n'), std::string::npos);
  EXPECT_EQ(brief.rfind(VerdictName(r.verdict), 0), 0u) << brief;
  EXPECT_NE(brief.find("mean |dz|"), std::string::npos) << brief;
}

// wide_search auto's rule (align_result.h), case by case against its
// definition: failed, not improved while apart, or improved but apart;
// without a sampling gap there is nothing to call apart.
TEST(AlignApiTest, WideSearchWantedFollowsTheVerdictAndTheSamplingGap) {
  const auto result = [](Verdict verdict, double gap, double mean_abs_dz, double rho_d_axial) {
    AlignResult r;
    r.verdict = verdict;
    r.sampling_gap = gap;
    r.after.mean_abs_dz = mean_abs_dz;
    r.after.rho_d_axial = rho_d_axial;
    return r;
  };
  const CostKind volume = CostKind::kVolume, axial = CostKind::kAxial;
  EXPECT_TRUE(WideSearchWanted(result(Verdict::kFailed, 1.0, 0.1, 0.1), volume));
  EXPECT_FALSE(WideSearchWanted(result(Verdict::kConvergedImproved, 1.0, 0.5, 5.0), volume));
  EXPECT_FALSE(WideSearchWanted(result(Verdict::kConvergedImproved, 1.0, 1.0, 5.0), volume));  // at the gap: close
  EXPECT_TRUE(WideSearchWanted(result(Verdict::kConvergedImproved, 1.0, 1.5, 0.5), volume));
  // An axial cost is judged by ρ'd.
  EXPECT_TRUE(WideSearchWanted(result(Verdict::kConvergedImproved, 1.0, 0.5, 1.5), axial));
  EXPECT_FALSE(WideSearchWanted(result(Verdict::kConvergedImproved, 1.0, 1.5, 0.5), axial));
  // A start at the minimum does not improve, but lies close: nothing to find.
  EXPECT_FALSE(WideSearchWanted(result(Verdict::kConvergedNotImproved, 1.0, 0.5, 0.5), volume));
  EXPECT_TRUE(WideSearchWanted(result(Verdict::kConvergedNotImproved, 1.0, 1.5, 1.5), volume));
  // No sampling gap known (e.g. a plane): never apart, so only a result
  // that did not improve asks.
  EXPECT_FALSE(WideSearchWanted(result(Verdict::kConvergedImproved, 0.0, 1.5, 1.5), volume));
  EXPECT_TRUE(WideSearchWanted(result(Verdict::kConvergedNotImproved, 0.0, 1.5, 1.5), volume));
  // Ill-conditioned: the solve improved; what it left undetermined is not a wrong minimum.
  EXPECT_FALSE(WideSearchWanted(result(Verdict::kIllConditioned, 1.0, 1.5, 1.5), volume));
}

}  // namespace
}  // namespace surfreg

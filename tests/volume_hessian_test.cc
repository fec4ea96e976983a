// The volume cost's interior curvature (registration/volume_cost/volume_hessian.h)
// against a closed form (a V-shaped surface under a level plane), against
// central differences of the exact gradient (A inside B, so Ω does not
// move), and the overlay cache's version against the cell walk's.
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "registration/pair_state.h"
#include "registration/volume_cost/volume_cost.h"
#include "registration/volume_cost/volume_hessian.h"
#include "testing/registration_sides.h"

namespace surfreg {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

std::vector<std::array<double, 3>> Grid(double x0, double x1, double y0, double y1,
                                        double (*height)(double, double)) {
  std::vector<std::array<double, 3>> points;
  for (double x = x0; x <= x1 + 1e-9; x += 1.0) {
    for (double y = y0; y <= y1 + 1e-9; y += 1.0) points.push_back({x, y, height(x, y)});
  }
  return points;
}

// The cache's version, after the Evaluate it needs.
Matrix6 FromCache(const PairState& state, bool parallel) {
  VolumeCostCache cache;
  cache.Evaluate(state, true, Execution{parallel ? 2 : 1});
  return cache.InteriorHessian(state, Execution{parallel ? 2 : 1});
}

// A: the plane z = c over [−10, 10] × [0, 10]; B: z = |x| over a larger
// grid (Ω is A's rectangle, whatever small motion B makes). d = |x| − c is
// zero on x = ±c (g_tz = 1, g_tx = ∓1, |∇d| = 1) and B kinks by κ = 2 on
// x = 0 where d = −c < 0 (w_tx = ±1). Per unit length in y:
//   ∂²/∂tz² ∫|d| = 2 (1 + 1) = 4,  ∂²/∂tx² ∫|d| = 2 (1 + 1) − 2 = 2
// (the second also from ∫ ||x − t| − c| dx = const + t²), no tx–tz or ty
// terms.
TEST(VolumeHessianTest, VShapeUnderAPlaneHasTheClosedForm) {
  const auto sides = MakeSides(Grid(-10, 10, 0, 10, [](double, double) { return 2.5; }),
                               Grid(-15, 15, -5, 15, [](double x, double) { return std::fabs(x); }));
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  const double length = 10;
  for (bool parallel : {false, true}) {
    for (const Matrix6& h : {InteriorVolumeHessian(state, Execution{parallel ? 2 : 1}), FromCache(state, parallel)}) {
      EXPECT_NEAR(h(5, 5), 4 * length, 1e-9);
      EXPECT_NEAR(h(3, 3), 2 * length, 1e-9);
      EXPECT_NEAR(h(3, 5), 0, 1e-9);
      EXPECT_NEAR(h(4, 4), 0, 1e-9);
      EXPECT_NEAR(h(3, 4), 0, 1e-9);
    }
  }
}

// With the zero line along mesh edges (c = 2 on a unit grid: d = 0 on the
// edges x = ±2 of both meshes), each piece of it counts once.
TEST(VolumeHessianTest, ZeroLineAlongEdgesCountsOnce) {
  const auto sides = MakeSides(Grid(-10, 10, 0, 10, [](double, double) { return 2.0; }),
                               Grid(-15, 15, -5, 15, [](double x, double) { return std::fabs(x); }));
  PairState state(sides->reference, sides->moving);
  ASSERT_TRUE(state.Update({0, 0, 0, 0, 0, 0}));
  for (const Matrix6& h : {InteriorVolumeHessian(state, Execution{1}), FromCache(state, false)}) {
    EXPECT_NEAR(h(5, 5), 40, 1e-9);
    EXPECT_NEAR(h(3, 3), 20, 1e-9);
  }
}

// Central differences of the exact gradient ∇∫μ|d| on noisy terrain (A's
// samples inside B's, so only the interior moves): the translation block
// has no other term and matches to the differences' accuracy; the rotation
// rows leave out ∫ μ sign(d) ∂_θg within the triangles, small here.
TEST(VolumeHessianTest, MatchesCentralDifferencesOfTheGradient) {
  auto noisy = [](std::vector<std::array<double, 3>> points, double amplitude) {
    for (std::size_t k = 0; k < points.size(); ++k) points[k][2] += amplitude * std::sin(12.9898 * k + 78.233 * k * k);
    return points;
  };
  for (bool weighted : {false, true}) {
    const auto sides =
        MakeSides(noisy(testing::SampleUniform(testing::SmoothTerrain, 2500, 20, 80, 20, 80, 11), 0.05),
                  noisy(testing::SampleUniform(testing::SmoothTerrain, 5000, 0, 100, 0, 100, 23), 0.05),
                  weighted ? WeightFunction(SmoothWeight) : WeightFunction());
    PairState state(sides->reference, sides->moving);
    const Theta theta = {0.001, -0.002, 0.0015, 0.05, -0.03, 0.01};
    ASSERT_TRUE(state.Update(theta));
    const Matrix6 h = InteriorVolumeHessian(state, Execution{1});
    Matrix6 fd = Matrix6::Zero();
    for (int k = 0; k < 6; ++k) {
      const double step = k < 3 ? 2e-5 : 2e-3;
      Theta plus = theta, minus = theta;
      plus[k] += step, minus[k] -= step;
      ASSERT_TRUE(state.Update(plus));
      const Vector6 gp = EvaluateVolumeCost(state, true, Execution{1}).d_abs;
      ASSERT_TRUE(state.Update(minus));
      const Vector6 gm = EvaluateVolumeCost(state, true, Execution{1}).d_abs;
      fd.col(k) = (gp - gm) / (2 * step);
    }
    ASSERT_TRUE(state.Update(theta));
    const Matrix6 sym = 0.5 * (fd + fd.transpose());
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        const double scale = std::sqrt(std::fabs(sym(i, i) * sym(j, j)));
        const double tolerance = (i >= 3 && j >= 3 ? 0.02 : 0.05) * scale;
        EXPECT_NEAR(h(i, j), sym(i, j), tolerance) << "weighted " << weighted << " (" << i << ", " << j << ")";
      }
    }
    // The overlay cache's version equals the cell walk's, on one thread or two.
    EXPECT_EQ(FromCache(state, false).isApprox(h, 1e-9), true);
    EXPECT_EQ(FromCache(state, true).isApprox(h, 1e-9), true);
  }
}

}  // namespace
}  // namespace surfreg

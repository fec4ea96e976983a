// The spatially correlated DoD error model (terrain/variogram.h,
// terrain/spatial_budget.h, terrain/dod_error.h) against brute force and
// closed forms.
#include "terrain/dod_error.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "terrain/change_budget.h"
#include "terrain/spatial_budget.h"
#include "terrain/variogram.h"

namespace surfreg {
namespace {

TEST(VariogramTest, SphericalModelValues) {
  EXPECT_EQ(SphericalCorrelation(0, 5), 1);
  EXPECT_NEAR(SphericalCorrelation(2.5, 5), 1 - 0.75 + 0.0625, 1e-15);
  EXPECT_EQ(SphericalCorrelation(5, 5), 0);
  EXPECT_EQ(SphericalCorrelation(7, 5), 0);
  EXPECT_EQ(SphericalCorrelation(1e9, HUGE_VAL), 1);
  EXPECT_EQ(SphericalCorrelation(1, 0), 0);  // no range: a nugget
  Variogram v;
  v.nugget = 0.2, v.sill = {0.5, 0.3}, v.range = {4, 40};
  EXPECT_EQ(v.Gamma(0), 0);
  EXPECT_EQ(v.Correlation(0), 1);
  EXPECT_NEAR(v.Gamma(1e-9), 0.2, 1e-9);
  EXPECT_NEAR(v.Gamma(50), 1.0, 1e-15);
  EXPECT_NEAR(v.Correlation(20), 0.3 * SphericalCorrelation(20, 40), 1e-15);
}

// The model's own semivariances at the lags of bins are fitted back.
TEST(VariogramTest, FitRecoversAnExactModel) {
  Variogram truth;
  truth.nugget = 0.2, truth.sill = {0.5, 0.3}, truth.range = {6, 60};
  EmpiricalVariogram e;
  for (double h = 1; h < 150; h *= 1.25) {
    e.lag.push_back(h);
    e.gamma.push_back(truth.Gamma(h));
    e.pairs.push_back(10000);
  }
  const Variogram fit = FitVariogram(e, 0.5, 300);
  EXPECT_NEAR(fit.nugget, 0.2, 0.01);
  EXPECT_NEAR(fit.sill[0], 0.5, 0.01);
  EXPECT_NEAR(fit.sill[1], 0.3, 0.01);
  EXPECT_NEAR(fit.range[0], 6, 0.06);
  EXPECT_NEAR(fit.range[1], 60, 0.6);
  // A flat variogram is a nugget; too few bins: their mean.
  EmpiricalVariogram flat = e;
  for (double& g : flat.gamma) g = 0.7;
  const Variogram nugget = FitVariogram(flat, 0.5, 300);
  EXPECT_NEAR(nugget.nugget, 0.7, 1e-9);
  EXPECT_NEAR(nugget.sill[0] + nugget.sill[1], 0, 1e-9);
  EmpiricalVariogram two{{1, 2}, {0.5, 0.7}, {10, 10}};  // weights pairs / γ²
  EXPECT_NEAR(FitVariogram(two, 0.5, 10).nugget, (40 * 0.5 + 10 / 0.49 * 0.7) / (40 + 10 / 0.49),
              1e-12);
  // Noise of 1% about a flat variogram is no correlation; a dip of 20% at the first lag is.
  EmpiricalVariogram noisy = flat;
  for (std::size_t b = 0; b < noisy.gamma.size(); ++b)
    noisy.gamma[b] *= 1 + 0.01 * std::sin(3.0 * b);
  EXPECT_EQ(FitVariogram(noisy, 0.5, 300).sill[1], 0);
  noisy.gamma[0] *= 0.8;
  EXPECT_GT(FitVariogram(noisy, 0.5, 300).sill[1], 0);
}

// White noise of variance 1: Dowd's semivariance is 1 at every lag.
TEST(VariogramTest, SampledVariogramOfWhiteNoise) {
  GridLayout grid{150, 120, 2.0, 2.0};
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  std::vector<double> values(static_cast<std::size_t>(grid.cells()));
  for (double& v : values) v = normal(random);
  values[5] = std::nan("");  // holes are skipped
  const EmpiricalVariogram e = SampleVariogram(grid, values, Execution{2}, 5000);
  ASSERT_GE(e.lag.size(), 10u);
  EXPECT_NEAR(e.lag.front(), 2.0, 0.01);  // the first bin: neighbours one cell apart
  for (std::size_t b = 0; b < e.lag.size(); ++b) {
    EXPECT_NEAR(e.gamma[b], 1.0, 0.08) << "lag " << e.lag[b];
    if (b > 0) {
      EXPECT_GT(e.lag[b], e.lag[b - 1]);
    }
  }
  // The same bins for one thread and two.
  const EmpiricalVariogram one = SampleVariogram(grid, values, Execution{1}, 5000);
  EXPECT_EQ(one.gamma, e.gamma);
  EXPECT_EQ(one.lag, e.lag);
}

double SquareRootKernel(double h, const void*) { return std::max(0.0, 1 - std::sqrt(h) / 3); }
double OneKernel(double, const void*) { return 1; }

// Σ_ij w_i w_j K(d_ij) against the double loop over every pair of cells.
TEST(SpatialBudgetTest, QuadraticFormIsTheDoubleSum) {
  GridLayout grid{23, 17, 1.0, 1.5};
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> uniform(-1, 2);
  std::vector<double> w(static_cast<std::size_t>(grid.cells()));
  for (double& v : w) v = uniform(random);
  for (int k = 0; k < 40; ++k) w[static_cast<std::size_t>(k * 7)] = 0;  // cells without a node
  double brute = 0;
  for (int64_t i = 0; i < grid.cells(); ++i) {
    for (int64_t j = 0; j < grid.cells(); ++j) {
      const double d = std::hypot((i % grid.columns - j % grid.columns) * grid.dx,
                                  (i / grid.columns - j / grid.columns) * grid.dy);
      if (d < 9) brute += w[i] * w[j] * SquareRootKernel(d, nullptr);
    }
  }
  int block = 0;
  const double fast =
      KernelQuadraticForm(grid, w, SquareRootKernel, nullptr, 9, Execution{2}, 1e8, &block);
  EXPECT_EQ(block, 1);
  EXPECT_NEAR(fast, brute, 1e-11 * std::fabs(brute));
  EXPECT_EQ(KernelQuadraticForm(grid, w, SquareRootKernel, nullptr, 9, Execution{1}),
            fast);  // any threads
  // A constant kernel over blocks is exact too: (Σ w)².
  double sum = 0;
  for (double v : w) sum += v;
  const double blocked =
      KernelQuadraticForm(grid, w, OneKernel, nullptr, HUGE_VAL, Execution{1}, 2e3, &block);
  EXPECT_GT(block, 1);
  EXPECT_NEAR(blocked, sum * sum, 1e-10 * sum * sum);
}

// E[g Z], E[g (Z² − 1)] and Var g − c₁² − c₂²/2 by quadrature over Z.
HermiteTerms NumericTerms(double dz, double sigma, double l) {
  const double mu = std::fabs(dz) > l ? dz : 0.0;
  double moments[3][4] = {};  // [fill, cut, net][E g, E g², E g Z, E g (Z² − 1)]
  const double step = 1e-4;
  for (double z = -12; z <= 12; z += step) {
    const double weight = std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI) * step;
    const double x = mu + sigma * z;
    const double g[3] = {x > l ? x : 0.0, x < -l ? -x : 0.0, (x > l || x < -l) ? x : 0.0};
    for (int k = 0; k < 3; ++k) {
      moments[k][0] += weight * g[k], moments[k][1] += weight * g[k] * g[k];
      moments[k][2] += weight * g[k] * z, moments[k][3] += weight * g[k] * (z * z - 1);
    }
  }
  HermiteTerms t;
  for (int k = 0; k < 3; ++k) {
    t.c1[k] = moments[k][2], t.c2[k] = moments[k][3];
    t.rest[k] =
        moments[k][1] - moments[k][0] * moments[k][0] - t.c1[k] * t.c1[k] - 0.5 * t.c2[k] * t.c2[k];
  }
  return t;
}

TEST(SpatialBudgetTest, HermiteTermsMatchQuadrature) {
  for (const auto& [dz, sigma, l] : std::vector<std::array<double, 3>>{{0.3, 0.5, 0.98},
                                                                       {2.0, 0.5, 0.98},
                                                                       {-1.2, 0.5, 0.98},
                                                                       {5.0, 0.4, 1.0},
                                                                       {0.1, 1.0, 0.0},
                                                                       {-0.7, 2.0, 0.0}}) {
    const HermiteTerms t = CellHermiteTerms(dz, sigma, l), q = NumericTerms(dz, sigma, l);
    const double tolerance = 2e-3 * sigma * sigma + 1e-6;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(t.c1[k], q.c1[k], tolerance) << dz << " " << l << " budget " << k;
      EXPECT_NEAR(t.c2[k], q.c2[k], tolerance) << dz << " " << l << " budget " << k;
      EXPECT_NEAR(t.rest[k], std::max(0.0, q.rest[k]), tolerance)
          << dz << " " << l << " budget " << k;
    }
  }
  // No threshold: the net is linear, c₁ = σ and nothing is left.
  const HermiteTerms linear = CellHermiteTerms(0.4, 0.3, 0);
  EXPECT_NEAR(linear.c1[HermiteTerms::kNet], 0.3, 1e-15);
  EXPECT_NEAR(linear.c2[HermiteTerms::kNet], 0, 1e-15);
  EXPECT_NEAR(linear.rest[HermiteTerms::kNet], 0, 1e-15);
  // No change detected: the net's g is odd, c₂ = 0.
  EXPECT_NEAR(CellHermiteTerms(0.2, 0.5, 0.98).c2[HermiteTerms::kNet], 0, 1e-15);
  EXPECT_EQ(CellHermiteTerms(1, 0, 0.5).c1[HermiteTerms::kNet], 0);  // σ = 0: no error
  // Known stable terrain: a cell detected by chance is noise (μ = 0), as one below the threshold.
  const HermiteTerms chance = CellHermiteTerms(1.2, 0.5, 0.98, /*noise=*/true),
                     none = CellHermiteTerms(0.0, 0.5, 0.98);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(chance.c1[k], none.c1[k]);
    EXPECT_EQ(chance.rest[k], none.rest[k]);
  }
  EXPECT_NE(CellHermiteTerms(1.2, 0.5, 0.98).c1[HermiteTerms::kFill], none.c1[HermiteTerms::kFill]);
}

// A DoD with heteroscedastic σ and node areas; no threshold.
struct Dod {
  GridLayout grid{40, 30, 2.0, 2.0};
  std::vector<double> dz, sigma, threshold, area;
  Dod() {
    std::mt19937_64 random(11);
    std::normal_distribution<double> normal;
    for (int64_t i = 0; i < grid.cells(); ++i) {
      dz.push_back(i % 9 == 0 ? std::nan("") : normal(random));
      sigma.push_back(0.2 + 0.01 * static_cast<double>(i % 13));
      area.push_back(i % 5 == 0 ? 2.0 : 4.0);
      threshold.push_back(0);
    }
  }
};

// The two bounds of terrain/change_budget.h are the model's two limits:
// a pure nugget (no correlation) and an infinite range (one error everywhere).
TEST(SpatialBudgetTest, NuggetAndInfiniteRangeAreTheTwoBounds) {
  const Dod d;
  const ChangeBudget bounds = ComputeChangeBudget(d.dz, d.area, d.sigma, 0, 0);
  Variogram nugget;
  nugget.nugget = 0.9;
  const SpatialSigma independent =
      PropagateSpatialSigma(d.grid, d.dz, d.sigma, d.threshold, d.area, nugget, Execution{1});
  EXPECT_NEAR(independent.net, bounds.net_sigma_independent, 1e-12 * bounds.net_sigma_independent);
  Variogram infinite;
  infinite.sill = {0, 1.3}, infinite.range = {0, HUGE_VAL};
  const SpatialSigma correlated =
      PropagateSpatialSigma(d.grid, d.dz, d.sigma, d.threshold, d.area, infinite, Execution{2});
  EXPECT_NEAR(correlated.net, bounds.net_sigma_correlated, 1e-10 * bounds.net_sigma_correlated);
  // Between them, a finite range.
  Variogram finite;
  finite.nugget = 0.3, finite.sill = {0, 0.7}, finite.range = {0, 10};
  const SpatialSigma between =
      PropagateSpatialSigma(d.grid, d.dz, d.sigma, d.threshold, d.area, finite, Execution{1});
  EXPECT_GT(between.net, independent.net);
  EXPECT_LT(between.net, correlated.net);
  EXPECT_EQ(between.block, 1);
}

// A threshold with every cell beyond it by far: the budget is linear again.
TEST(SpatialBudgetTest, ChangeFarBeyondTheThresholdIsLinear) {
  Dod d;
  for (double& v : d.dz) {
    if (std::isfinite(v)) v = v > 0 ? 10 + v : -10 + v;
  }
  for (double& t : d.threshold) t = 1;
  Variogram nugget;
  nugget.nugget = 1;
  const SpatialSigma s =
      PropagateSpatialSigma(d.grid, d.dz, d.sigma, d.threshold, d.area, nugget, Execution{1});
  const ChangeBudget bounds = ComputeChangeBudget(d.dz, d.area, d.sigma, 0, 1);
  EXPECT_NEAR(s.net, bounds.net_sigma_independent, 1e-9 * s.net);
  EXPECT_NEAR(s.fill, bounds.fill_sigma_independent, 1e-9 * s.fill);
  EXPECT_NEAR(s.cut, bounds.cut_sigma_independent, 1e-9 * s.cut);
}

// Monte Carlo: errors drawn from the model's own covariance (Cholesky) on
// a 24 x 24 DoD with a block of change; the spread of the net's error
// against the propagated σ, without a threshold (exact) and at 95% (an
// upper bound, within 25%).
TEST(SpatialBudgetTest, ThresholdedNetAgainstMonteCarlo) {
  const GridLayout grid{24, 24, 1.0, 1.0};
  const int n = static_cast<int>(grid.cells());
  Variogram v;
  v.nugget = 0.3, v.sill = {0, 0.7}, v.range = {0, 5};
  const double sigma = 0.5;
  Eigen::MatrixXd covariance(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double d = std::hypot(i % 24 - j % 24, i / 24 - j / 24);
      covariance(i, j) = sigma * sigma * v.Correlation(d);
    }
  }
  const Eigen::MatrixXd root = covariance.llt().matrixL();
  std::vector<double> change(static_cast<std::size_t>(n), 0.0), area(change.size(), 1.0);
  for (int i = 0; i < n; ++i) {
    if (i % 24 < 8 && i / 24 < 8) change[static_cast<std::size_t>(i)] = 3.0;
  }
  std::mt19937_64 random(17);
  std::normal_distribution<double> normal;
  for (const double confidence : {0.0, 0.95}) {
    const double l = confidence > 0 ? TwoSidedNormalQuantile(confidence) * sigma : 0.0;
    std::vector<double> errors, sigmas;
    double true_net = 0;
    for (double c : change) true_net += c;
    for (int draw = 0; draw < 4000; ++draw) {
      Eigen::VectorXd z(n);
      for (int i = 0; i < n; ++i) z[i] = normal(random);
      const Eigen::VectorXd e = root * z;
      std::vector<double> dz(change.size());
      double net = 0;
      for (int i = 0; i < n; ++i) {
        dz[static_cast<std::size_t>(i)] = change[static_cast<std::size_t>(i)] + e[i];
        if (std::fabs(dz[static_cast<std::size_t>(i)]) > l) net += dz[static_cast<std::size_t>(i)];
      }
      errors.push_back(net - true_net);
      if (draw < 100) {
        const std::vector<double> s(change.size(), sigma), t(change.size(), l);
        sigmas.push_back(PropagateSpatialSigma(grid, dz, s, t, area, v, Execution{1}).net);
      }
    }
    double mean = 0, square = 0;
    for (double x : errors) mean += x / errors.size();
    for (double x : errors) square += (x - mean) * (x - mean) / (errors.size() - 1);
    std::sort(sigmas.begin(), sigmas.end());
    const double propagated = sigmas[sigmas.size() / 2], spread = std::sqrt(square);
    if (confidence == 0) {
      EXPECT_NEAR(propagated / spread, 1.0, 0.04);
    } else {
      EXPECT_GE(propagated / spread, 0.97);
      EXPECT_LE(propagated / spread, 1.25);
    }
    std::printf("confidence %.2f: propagated %.3f, Monte Carlo %.3f\n", confidence, propagated,
                spread);
  }
}

TEST(DodErrorTest, SlopeAndCurvatureOfAPlaneAndAParaboloid) {
  GridLayout grid{9, 7, 0.5, 0.25};
  std::vector<double> plane, bowl;
  for (int y = 0; y < grid.rows; ++y) {
    for (int x = 0; x < grid.columns; ++x) {
      const double east = x * grid.dx, north = -y * grid.dy;  // row 0 at the top
      plane.push_back(2 * east + 3 * north);
      bowl.push_back(east * east + north * north);
    }
  }
  plane[20] = std::nan("");  // a hole: its neighbours go one-sided
  std::vector<double> slope, curvature;
  SlopeAndCurvature(grid, plane, &slope, &curvature);
  for (std::size_t i = 0; i < slope.size(); ++i) {
    if (i == 20) {
      EXPECT_TRUE(std::isnan(slope[i]));
      continue;
    }
    EXPECT_NEAR(slope[i], std::sqrt(13.0), 1e-9) << i;
  }
  SlopeAndCurvature(grid, bowl, &slope, &curvature);
  EXPECT_NEAR(curvature[3 * grid.columns + 4], 4.0, 1e-9);
}

// σ growing with slope is found in the bins; too little stable terrain is refused in one line.
TEST(DodErrorTest, SigmaGrowsWithSlopeAndTooLittleStableTerrainIsRefused) {
  DodGrid dod;
  dod.layout = {200, 100, 1.0, 1.0};
  DodBlock& c = dod.cells;
  c.columns = 200, c.rows = 100;
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal;
  for (int y = 0; y < dod.layout.rows; ++y) {
    for (int x = 0; x < dod.layout.columns; ++x) {
      const double slope = 0.01 * x;  // z = 0.005 x², slope 0.01 x
      c.height.push_back(0.005 * x * x);
      c.dz.push_back((0.1 + slope) * normal(random));
      c.area.push_back(1);
      c.stable.push_back(1);
    }
  }
  const DodBlockReader read = DodGridReader(dod);
  const DodErrorModel model = FitDodErrorModel(dod.layout, read, Execution{1}, "key 'error_model'");
  EXPECT_TRUE(model.sigma_estimated);
  ASSERT_GE(model.sigma_model.slope.size(), 5u);
  for (std::size_t b = 0; b < model.sigma_model.slope.size(); ++b) {
    const double s = model.sigma_model.slope[b];
    EXPECT_NEAR(model.sigma_model.sigma[b], 0.1 + s, 0.1 * (0.1 + s)) << "slope " << s;
  }
  ASSERT_EQ(model.sigma_model.curvature.size(), 1u);  // one curvature: one bin, a factor of 1
  EXPECT_NEAR(model.sigma_model.factor[0], 1, 0.03);
  // σ of a window (its edge cells' slope from the cells around it).
  DodBlock window;
  window.column = 149, window.row = 50, window.columns = 3, window.rows = 2;
  std::vector<double> sigma;
  ReadWithSigma(dod.layout, read, model, &window, &sigma);
  ASSERT_EQ(sigma.size(), 6u);
  EXPECT_NEAR(sigma[1], 0.1 + 1.5, 0.15);
  EXPECT_EQ(window.dz[1], c.dz[50 * 200 + 150]);
  // The standardized dz is white: almost all nugget.
  EXPECT_GT(model.variogram.nugget, 0.8 * model.variogram.Total());
  std::fill(c.stable.begin(), c.stable.end(), 0);
  std::fill(c.stable.begin(), c.stable.begin() + 999, 1);
  try {
    FitDodErrorModel(dod.layout, read, Execution{1}, "key 'error_model'");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("key 'error_model': only ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs at least 1000"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(DodErrorTest, LargeGridsAreFittedOnSixteenWindows) {
  EXPECT_EQ(ErrorModelWindows({2048, 2048, 1, 1}).size(), 1u);
  const auto windows = ErrorModelWindows({5000, 1500, 1, 1});
  ASSERT_EQ(windows.size(), 16u);
  EXPECT_EQ(windows.front(), (std::array<int, 4>{0, 0, 1024, 1024}));
  EXPECT_EQ(windows.back(), (std::array<int, 4>{5000 - 1024, 1500 - 1024, 1024, 1024}));
  EXPECT_EQ(ErrorModelWindows({100000, 50, 1, 1}).size(), 4u);  // one row of windows: 50 rows
}

// Bands of rows (a wide grid: 16 rows a band) give the one-band sums.
TEST(SpatialBudgetTest, BandsAddUpToTheWholeGrid) {
  GridLayout grid{65536, 40, 1.0, 1.0};
  ASSERT_EQ(PropagationBandRows(grid), 16);
  std::mt19937_64 random(13);
  std::normal_distribution<double> normal;
  std::vector<double> dz, sigma, threshold, area, u;
  for (int64_t i = 0; i < grid.cells(); ++i) {
    dz.push_back(normal(random));
    sigma.push_back(0.5 + 0.1 * static_cast<double>(i % 3));
    threshold.push_back(0);
    area.push_back(1);
    u.push_back(area.back() * sigma.back());
  }
  Variogram v;
  v.nugget = 0.4, v.sill = {0, 0.6}, v.range = {0, 3.5};
  const SpatialSigma s =
      PropagateSpatialSigma(grid, dz, sigma, threshold, area, v, Execution{2}, 1e9);
  struct Range {
    double r;
  } range{3.5};
  const auto kernel = [](double h, const void* data) {
    return 0.6 * SphericalCorrelation(h, static_cast<const Range*>(data)->r);
  };
  double diagonal = 0;
  for (double x : u) diagonal += x * x;
  const double whole =
      0.4 * diagonal + KernelQuadraticForm(grid, u, kernel, &range, 3.5, Execution{2}, 1e9);
  EXPECT_EQ(s.block, 1);
  EXPECT_NEAR(s.net * s.net, whole, 1e-10 * whole);
}

}  // namespace
}  // namespace surfreg

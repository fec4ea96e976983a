// Propagated uncertainty of change (terrain/change_budget.h) and the node
// areas it weights dz by (MeasureSummary::node_area_a), against closed forms.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "terrain/change_budget.h"
#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg {
namespace {

TEST(ChangeBudgetTest, TwoSidedNormalQuantiles) {
  // Tabulated standard normal quantiles z_{(1+c)/2}.
  EXPECT_NEAR(TwoSidedNormalQuantile(0.95), 1.959963984540054, 1e-12);
  EXPECT_NEAR(TwoSidedNormalQuantile(0.90), 1.6448536269514722, 1e-12);
  EXPECT_NEAR(TwoSidedNormalQuantile(0.99), 2.5758293035489004, 1e-12);
  EXPECT_NEAR(TwoSidedNormalQuantile(0.6826894921370859), 1.0, 1e-12);
  EXPECT_NEAR(TwoSidedNormalQuantile(1e-9), 1e-9 * std::sqrt(M_PI / 2), 1e-15);
  for (double c : {0.0, 1.0, -0.5, 2.0, std::nan("")}) {
    EXPECT_THROW(TwoSidedNormalQuantile(c), std::invalid_argument) << c;
  }
}

// σ₁ = 0.3, σ₂ = 0.4: σ_DoD = 0.5 and at 95% L = 0.98. Nodes of area h²:
// n1 at +2 (gain), n2 at +0.5 and n3 at −0.9 (below L), n4 at −3 (loss),
// two outside Ω (NaN dz) and one with an unknown σ.
TEST(ChangeBudgetTest, ClosedFormsWithIndependentAndCorrelatedErrors) {
  const double h2 = 2.5 * 2.5;
  const int n1 = 7, n2 = 5, n3 = 4, n4 = 3;
  std::vector<double> dz, area, sa, sb;
  auto add = [&](int n, double d) {
    for (int i = 0; i < n; ++i) {
      dz.push_back(d);
      area.push_back(h2);
      sa.push_back(0.3);
      sb.push_back(0.4);
    }
  };
  add(n1, 2.0);
  add(n2, 0.5);
  add(n3, -0.9);
  add(n4, -3.0);
  add(2, std::nan(""));
  dz.push_back(5.0), area.push_back(h2), sa.push_back(std::nan("")), sb.push_back(0.4);
  const std::vector<double> sigma = PropagateSigma(sa, sb);
  EXPECT_DOUBLE_EQ(sigma[0], 0.5);
  EXPECT_TRUE(std::isnan(sigma.back()));
  const ChangeBudget b = ComputeChangeBudget(dz, area, sigma, 0.95, 0.0);
  EXPECT_NEAR(b.t, 1.959963984540054, 1e-12);
  EXPECT_EQ(b.nodes, n1 + n2 + n3 + n4);
  EXPECT_EQ(b.fill_nodes, n1);
  EXPECT_EQ(b.cut_nodes, n4);
  EXPECT_DOUBLE_EQ(b.fill, 2.0 * h2 * n1);
  EXPECT_DOUBLE_EQ(b.cut, 3.0 * h2 * n4);
  EXPECT_DOUBLE_EQ(b.net, (2.0 * n1 - 3.0 * n4) * h2);
  EXPECT_DOUBLE_EQ(b.fill_area, h2 * n1);
  EXPECT_DOUBLE_EQ(b.cut_area, h2 * n4);
  EXPECT_NEAR(b.fill_sigma_independent, 0.5 * h2 * std::sqrt(n1), 1e-12);
  EXPECT_NEAR(b.cut_sigma_independent, 0.5 * h2 * std::sqrt(n4), 1e-12);
  EXPECT_NEAR(b.net_sigma_independent, 0.5 * h2 * std::sqrt(n1 + n4), 1e-12);
  EXPECT_NEAR(b.fill_sigma_correlated, 0.5 * h2 * n1, 1e-12);
  EXPECT_NEAR(b.cut_sigma_correlated, 0.5 * h2 * n4, 1e-12);
  EXPECT_NEAR(b.net_sigma_correlated, 0.5 * h2 * (n1 + n4), 1e-12);
  EXPECT_DOUBLE_EQ(b.sigma_median, 0.5);
  EXPECT_NEAR(b.threshold_median, 0.5 * 1.959963984540054, 1e-12);

  // A minimum level of detection above t σ wins: at 1.0 the −0.9 nodes stay
  // out; at 0.4 without a confidence they count, and so do the +0.5 ones.
  const ChangeBudget floor = ComputeChangeBudget(dz, area, sigma, 0.95, 1.0);
  EXPECT_EQ(floor.fill_nodes, n1);
  EXPECT_EQ(floor.cut_nodes, n4);
  EXPECT_DOUBLE_EQ(floor.threshold_median, 1.0);
  const ChangeBudget low = ComputeChangeBudget(dz, area, sigma, 0.0, 0.4);
  EXPECT_EQ(low.t, 0.0);
  EXPECT_EQ(low.fill_nodes, n1 + n2);
  EXPECT_EQ(low.cut_nodes, n3 + n4);
  EXPECT_DOUBLE_EQ(low.cut, (0.9 * n3 + 3.0 * n4) * h2);

  // Per-node σ: the thresholds follow it.
  std::vector<double> varying = sigma;
  varying[0] = 2.0;  // 2 < 1.96 × 2: this +2 node is no longer detected
  const ChangeBudget v = ComputeChangeBudget(dz, area, varying, 0.95, 0.0);
  EXPECT_EQ(v.fill_nodes, n1 - 1);
  EXPECT_NEAR(v.fill_sigma_correlated, 0.5 * h2 * (n1 - 1), 1e-12);
  const std::vector<double> l = ChangeThresholds(varying, 0.95, 0.0);
  EXPECT_NEAR(l[0], 2.0 * 1.959963984540054, 1e-12);
  EXPECT_TRUE(std::isnan(l.back()));
  EXPECT_THROW(ComputeChangeBudget(dz, area, std::vector<double>(3, 0.5), 0.95, 0.0),
               std::invalid_argument);
}

// A raster surface of columns × rows nodes at spacing h (cells set, so it is
// meshed on its cells) with heights z(c, r).
template <typename Height>
Surface Grid(int columns, int rows, double h, Height z) {
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      points.push_back({1000.0 + c * h, 2000.0 - r * h, z(c, r)});
      cells.push_back({c, r});
    }
  }
  Surface s = MakeSurface(points, {}, "grid");
  s.raster_cell = cells;
  return s;
}

// On two rasters of one grid, Ω is the whole grid: an inner node stands for
// its cell, h², an edge node for h²/2, and the areas add up to the grid's.
// A −8 block of N inner nodes then has the cellwise cut 8 h² N.
TEST(ChangeBudgetTest, NodeAreasOfARasterAreItsCells) {
  const int columns = 12, rows = 9;
  const double h = 2.5;
  const Surface a = Grid(columns, rows, h, [](int c, int r) { return 0.1 * c - 0.05 * r * r; });
  const auto in_block = [](int c, int r) { return c >= 3 && c < 7 && r >= 2 && r < 5; };
  const Surface b = Grid(columns, rows, h, [&](int c, int r) {
    return 0.1 * c - 0.05 * r * r - (in_block(c, r) ? 8.0 : 0.0);
  });
  MeasureOptions options;
  options.keep_node_gaps = true;
  options.threads = 1;
  const MeasureSummary s = Measure(a, b, options);
  ASSERT_EQ(s.node_area_a.size(), a.size());
  double sum = 0;
  std::vector<double> sigma(a.size(), 0.5);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const double area = s.node_area_a[r * columns + c];
      sum += area;
      const bool edge_c = c == 0 || c == columns - 1, edge_r = r == 0 || r == rows - 1;
      if (!edge_c && !edge_r) {
        EXPECT_NEAR(area, h * h, 1e-9) << c << ", " << r;
      } else if (edge_c != edge_r) {
        EXPECT_NEAR(area, h * h / 2, 1e-9) << c << ", " << r;
      }
    }
  }
  EXPECT_NEAR(sum, (columns - 1) * (rows - 1) * h * h, 1e-8);
  EXPECT_NEAR(sum, s.overlap_area, 1e-8);
  const ChangeBudget budget = ComputeChangeBudget(s.dz_a, s.node_area_a, sigma, 0.95, 0.0);
  EXPECT_EQ(budget.cut_nodes, 12);
  EXPECT_EQ(budget.fill_nodes, 0);
  EXPECT_NEAR(budget.cut, 8 * h * h * 12, 1e-9);
  EXPECT_NEAR(budget.cut_sigma_independent, 0.5 * h * h * std::sqrt(12.0), 1e-9);
  // The exact overlay integral agrees for a block of whole cells' hats.
  EXPECT_NEAR(s.volume_below, 8 * h * h * 12, 1e-8);
}

// The sums in parts (as tiles and shards add them) give the budget of the
// whole; non-finite nodes are skipped; a node exactly at its threshold is
// no change.
TEST(ChangeBudget, SumsInPartsEqualTheWhole) {
  const std::vector<double> dz = {0.9, -1.4, 0.2, std::nan(""), 2.5, -0.3, -2.0, 0.5};
  const std::vector<double> area = {1.0, 2.0, 0.5, 1.0, 1.5, 1.0, std::nan(""), 3.0};
  const std::vector<double> sigma(dz.size(), 0.25);
  const ChangeBudget whole = ComputeChangeBudget(dz, area, sigma, 0.95, 0.5);
  const double t = TwoSidedNormalQuantile(0.95), threshold = std::max(0.5, t * 0.25);
  ChangeBudgetSums first, second;
  for (std::size_t i = 0; i < dz.size(); ++i) (i < 3 ? first : second).AddNode(dz[i], area[i], 0.25, threshold);
  first.Add(second);
  const ChangeBudget parts = FinishChangeBudget(first, t, 0.25, threshold);
  EXPECT_EQ(parts.nodes, 6);  // the NaN dz and the NaN area left out
  EXPECT_EQ(parts.nodes, whole.nodes);
  EXPECT_EQ(parts.fill_nodes, 2);  // 0.9, 2.5 (0.5 is at the threshold: no change)
  EXPECT_EQ(parts.cut_nodes, 1);   // -1.4
  EXPECT_EQ(parts.fill_nodes, whole.fill_nodes);
  EXPECT_EQ(parts.cut_nodes, whole.cut_nodes);
  EXPECT_DOUBLE_EQ(parts.fill, 0.9 + 2.5 * 1.5);
  EXPECT_DOUBLE_EQ(parts.fill, whole.fill);
  EXPECT_DOUBLE_EQ(parts.cut, whole.cut);
  EXPECT_DOUBLE_EQ(parts.net_sigma_independent, whole.net_sigma_independent);
  EXPECT_DOUBLE_EQ(parts.net_sigma_correlated, whole.net_sigma_correlated);
  EXPECT_DOUBLE_EQ(whole.threshold_median, threshold);
  EXPECT_DOUBLE_EQ(whole.sigma_median, 0.25);
}

}  // namespace
}  // namespace surfreg

#pragma once
// Change between two DEMs with propagated uncertainty, as geomorphic change
// detection does it (Wheaton et al. 2010, GCD; Lane et al. 2003): each DEM
// has a vertical standard error σ₁, σ₂ (one number, or one per cell); the
// DoD's is σ_DoD = √(σ₁² + σ₂²) per node (errors of the two surveys
// independent); a node counts as change only where |dz| exceeds its
// threshold L = max(min_lod, t · σ_DoD), t the two-sided normal quantile of
// the chosen confidence; and the volumes are cellwise sums over the nodes,
// each standing for its area (MeasureSummary::node_area_a), with their
// uncertainty two ways: errors independent from node to node (√Σ(σ a)²,
// the usual and optimistic figure) and fully correlated (Σ σ a, a bias of
// σ everywhere: the pessimistic bound).
#include <cstdint>
#include <vector>

namespace surfreg {

// t with P(|Z| ≤ t) = confidence for a standard normal Z, confidence in
// (0, 1): 1.959964 for 0.95, 1.644854 for 0.90. Accurate to 1e-12.
double TwoSidedNormalQuantile(double confidence);

// σ_DoD at each node: √(σ_a² + σ_b²); NaN where either is NaN. Sizes must agree.
std::vector<double> PropagateSigma(const std::vector<double>& sigma_a, const std::vector<double>& sigma_b);

struct ChangeBudget {
  double t = 0;  // the threshold's multiple of σ_DoD (0: none)
  double fill = 0, cut = 0, net = 0;   // Σ dz a over detected gain; Σ |dz| a over loss; fill − cut
  double fill_area = 0, cut_area = 0;  // Σ a over the nodes of detected gain / loss
  int64_t fill_nodes = 0, cut_nodes = 0;
  // ± one standard error: nodes independent, and fully correlated.
  double fill_sigma_independent = 0, cut_sigma_independent = 0, net_sigma_independent = 0;
  double fill_sigma_correlated = 0, cut_sigma_correlated = 0, net_sigma_correlated = 0;
  int64_t nodes = 0;          // nodes with a finite dz, σ_DoD and area
  double sigma_median = 0;    // of σ_DoD over those nodes (NaN if none)
  double threshold_median = 0;  // of L over those nodes (NaN if none)
};

// The budget's sums over nodes, added node by node in any order and in
// parts (tiles, shards of a tiled measure: terrain/tiled_partial.h).
struct ChangeBudgetSums {
  int64_t nodes = 0, fill_nodes = 0, cut_nodes = 0;
  double fill = 0, cut = 0, fill_area = 0, cut_area = 0;
  double fill_var = 0, cut_var = 0;      // Σ (σ a)² over gain / loss
  double fill_sigma = 0, cut_sigma = 0;  // Σ σ a over gain / loss
  // A node with threshold L: skipped unless dz, area and σ_DoD are finite.
  void AddNode(double dz, double area, double sigma_dod, double threshold);
  void Add(const ChangeBudgetSums& other);
};

// The budget of `sums` at multiple t, with the medians of σ_DoD and of L
// over the nodes (NaN if none).
ChangeBudget FinishChangeBudget(const ChangeBudgetSums& sums, double t, double sigma_median,
                                double threshold_median);

// The budget over the nodes with a finite dz and σ_DoD (the others, e.g.
// outside Ω, are left out). `confidence` in (0, 1) sets t; 0 = no
// probabilistic threshold (t = 0, L = min_lod). min_lod >= 0. A node with
// dz > L is gain, dz < −L loss (|dz| ≤ L: no detected change); its whole dz
// counts, as in GCD. Sizes of dz, area and sigma_dod must agree.
ChangeBudget ComputeChangeBudget(const std::vector<double>& dz, const std::vector<double>& area,
                                 const std::vector<double>& sigma_dod, double confidence, double min_lod);

// The threshold L at each node (NaN where σ_DoD is), for figures and rasters.
std::vector<double> ChangeThresholds(const std::vector<double>& sigma_dod, double confidence, double min_lod);

}  // namespace surfreg

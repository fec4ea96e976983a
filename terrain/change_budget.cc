#include "terrain/change_budget.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace surfreg {
namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  const std::size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + half, values.end());
  const double upper = values[half];
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + half));
}

}  // namespace

double TwoSidedNormalQuantile(double confidence) {
  if (!(confidence > 0 && confidence < 1)) throw std::invalid_argument("confidence must be in (0, 1)");
  // Newton on erf(t / √2) = confidence, from above the root (a Gaussian
  // tail bound). erf is increasing and concave for t > 0, so after the first
  // step every iterate lies below the root and rises to it; t ≥ 0 is kept.
  double t = std::sqrt(-2.0 * std::log(0.5 * (1.0 - confidence)));
  for (int i = 0; i < 200; ++i) {
    const double f = std::erf(t / std::sqrt(2.0)) - confidence;
    const double slope = std::sqrt(2.0 / M_PI) * std::exp(-0.5 * t * t);
    const double next = std::max(0.0, t - f / slope);
    const bool done = std::fabs(next - t) <= 1e-15 * next;
    t = next;
    if (done) break;
  }
  return t;
}

std::vector<double> PropagateSigma(const std::vector<double>& sigma_a, const std::vector<double>& sigma_b) {
  if (sigma_a.size() != sigma_b.size()) throw std::invalid_argument("PropagateSigma: sizes differ");
  std::vector<double> out(sigma_a.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::hypot(sigma_a[i], sigma_b[i]);
  return out;
}

std::vector<double> ChangeThresholds(const std::vector<double>& sigma_dod, double confidence, double min_lod) {
  const double t = confidence > 0 ? TwoSidedNormalQuantile(confidence) : 0.0;
  std::vector<double> out(sigma_dod.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = std::isfinite(sigma_dod[i]) ? std::max(min_lod, t * sigma_dod[i]) : std::nan("");
  }
  return out;
}

void ChangeBudgetSums::AddNode(double dz, double area, double sigma_dod, double threshold) {
  if (!std::isfinite(dz) || !std::isfinite(sigma_dod) || !std::isfinite(area)) return;
  ++nodes;
  const double error = sigma_dod * area;
  if (dz > threshold) {
    fill += dz * area;
    fill_area += area;
    ++fill_nodes;
    fill_var += error * error;
    fill_sigma += error;
  } else if (dz < -threshold) {
    cut -= dz * area;
    cut_area += area;
    ++cut_nodes;
    cut_var += error * error;
    cut_sigma += error;
  }
}

void ChangeBudgetSums::Add(const ChangeBudgetSums& o) {
  nodes += o.nodes, fill_nodes += o.fill_nodes, cut_nodes += o.cut_nodes;
  fill += o.fill, cut += o.cut, fill_area += o.fill_area, cut_area += o.cut_area;
  fill_var += o.fill_var, cut_var += o.cut_var;
  fill_sigma += o.fill_sigma, cut_sigma += o.cut_sigma;
}

ChangeBudget FinishChangeBudget(const ChangeBudgetSums& s, double t, double sigma_median,
                                double threshold_median) {
  ChangeBudget b;
  b.t = t;
  b.nodes = s.nodes;
  b.fill = s.fill, b.cut = s.cut, b.net = s.fill - s.cut;
  b.fill_area = s.fill_area, b.cut_area = s.cut_area;
  b.fill_nodes = s.fill_nodes, b.cut_nodes = s.cut_nodes;
  b.fill_sigma_independent = std::sqrt(s.fill_var);
  b.cut_sigma_independent = std::sqrt(s.cut_var);
  b.net_sigma_independent = std::sqrt(s.fill_var + s.cut_var);
  b.fill_sigma_correlated = s.fill_sigma;
  b.cut_sigma_correlated = s.cut_sigma;
  // A bias of σ everywhere raises the fill and lowers the cut alike: on the
  // net the two add.
  b.net_sigma_correlated = s.fill_sigma + s.cut_sigma;
  b.sigma_median = sigma_median;
  b.threshold_median = threshold_median;
  return b;
}

ChangeBudget ComputeChangeBudget(const std::vector<double>& dz, const std::vector<double>& area,
                                 const std::vector<double>& sigma_dod, double confidence, double min_lod) {
  if (dz.size() != area.size() || dz.size() != sigma_dod.size()) {
    throw std::invalid_argument("ComputeChangeBudget: sizes differ");
  }
  const std::vector<double> threshold = ChangeThresholds(sigma_dod, confidence, min_lod);
  ChangeBudgetSums sums;
  std::vector<double> sigmas, thresholds;
  for (std::size_t i = 0; i < dz.size(); ++i) {
    if (!std::isfinite(dz[i]) || !std::isfinite(sigma_dod[i]) || !std::isfinite(area[i])) continue;
    sigmas.push_back(sigma_dod[i]);
    thresholds.push_back(threshold[i]);
    sums.AddNode(dz[i], area[i], sigma_dod[i], threshold[i]);
  }
  return FinishChangeBudget(sums, confidence > 0 ? TwoSidedNormalQuantile(confidence) : 0.0,
                            Median(std::move(sigmas)), Median(std::move(thresholds)));
}

}  // namespace surfreg

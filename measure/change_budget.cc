#include "measure/change_budget.h"

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

ChangeBudget ComputeChangeBudget(const std::vector<double>& dz, const std::vector<double>& area,
                                 const std::vector<double>& sigma_dod, double confidence, double min_lod) {
  if (dz.size() != area.size() || dz.size() != sigma_dod.size()) {
    throw std::invalid_argument("ComputeChangeBudget: sizes differ");
  }
  ChangeBudget b;
  b.t = confidence > 0 ? TwoSidedNormalQuantile(confidence) : 0.0;
  const std::vector<double> threshold = ChangeThresholds(sigma_dod, confidence, min_lod);
  double fill_var = 0, cut_var = 0;
  std::vector<double> sigmas, thresholds;
  for (std::size_t i = 0; i < dz.size(); ++i) {
    if (!std::isfinite(dz[i]) || !std::isfinite(sigma_dod[i]) || !std::isfinite(area[i])) continue;
    ++b.nodes;
    sigmas.push_back(sigma_dod[i]);
    thresholds.push_back(threshold[i]);
    const double a = area[i], error = sigma_dod[i] * area[i];
    if (dz[i] > threshold[i]) {
      b.fill += dz[i] * a;
      b.fill_area += a;
      ++b.fill_nodes;
      fill_var += error * error;
      b.fill_sigma_correlated += error;
    } else if (dz[i] < -threshold[i]) {
      b.cut -= dz[i] * a;
      b.cut_area += a;
      ++b.cut_nodes;
      cut_var += error * error;
      b.cut_sigma_correlated += error;
    }
  }
  b.net = b.fill - b.cut;
  b.fill_sigma_independent = std::sqrt(fill_var);
  b.cut_sigma_independent = std::sqrt(cut_var);
  b.net_sigma_independent = std::sqrt(fill_var + cut_var);
  // A bias of σ everywhere raises the fill and lowers the cut alike: on the
  // net the two add.
  b.net_sigma_correlated = b.fill_sigma_correlated + b.cut_sigma_correlated;
  b.sigma_median = Median(sigmas);
  b.threshold_median = Median(thresholds);
  return b;
}

}  // namespace surfreg

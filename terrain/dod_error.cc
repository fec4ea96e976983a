#include "terrain/dod_error.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "measure/input_error.h"

namespace surfreg {
namespace {

constexpr double kNmadScale = 1.4826;
constexpr double kInlierNmads = 4;
constexpr int64_t kMinBinCells = 200;
constexpr int kSlopeBins = 10, kCurvatureBins = 6;

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

double Nmad(const std::vector<double>& v) {
  const double m = Median(v);
  std::vector<double> deviation(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) deviation[i] = std::fabs(v[i] - m);
  return kNmadScale * Median(std::move(deviation));
}

// Piecewise linear through (x, y), constant beyond the ends.
double Interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  if (x.empty()) return 1;
  if (!std::isfinite(at)) return y[y.size() / 2];
  if (at <= x.front()) return y.front();
  if (at >= x.back()) return y.back();
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
  const double t = (at - x[k - 1]) / (x[k] - x[k - 1]);
  return y[k - 1] + t * (y[k] - y[k - 1]);
}

// Quantile bins of `key` (pairs of key and value, sorted by key here):
// each bin's median key and the NMAD of its values. At most `bins` bins of
// at least kMinBinCells; one bin when there are fewer. A bin whose median
// key is not above the previous one's (keys equal to rounding) joins it.
void BinnedNmad(std::vector<std::pair<double, double>> samples, int bins, std::vector<double>* keys,
                std::vector<double>* nmads) {
  keys->clear(), nmads->clear();
  std::stable_sort(samples.begin(), samples.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  const int64_t n = static_cast<int64_t>(samples.size());
  if (n == 0) return;
  const double scale = std::max(std::fabs(samples.front().first), std::fabs(samples.back().first));
  const int count = static_cast<int>(std::max<int64_t>(1, std::min<int64_t>(bins, n / kMinBinCells)));
  auto median_key = [&](int64_t begin, int64_t end) {
    std::vector<double> key;
    for (int64_t i = begin; i < end; ++i) key.push_back(samples[static_cast<std::size_t>(i)].first);
    return Median(std::move(key));
  };
  std::vector<std::pair<int64_t, int64_t>> ranges;
  for (int b = 0; b < count; ++b) {
    const int64_t begin = n * b / count, end = n * (b + 1) / count;
    if (!ranges.empty() &&
        !(median_key(begin, end) > median_key(ranges.back().first, ranges.back().second) + 1e-9 * scale)) {
      ranges.back().second = end;
    } else {
      ranges.emplace_back(begin, end);
    }
  }
  for (const auto& [begin, end] : ranges) {
    std::vector<double> value;
    for (int64_t i = begin; i < end; ++i) value.push_back(samples[static_cast<std::size_t>(i)].second);
    const double s = Nmad(value);
    if (!(s > 0)) continue;
    keys->push_back(median_key(begin, end));
    nmads->push_back(s);
  }
}

}  // namespace

void SlopeAndCurvature(const GridLayout& grid, const std::vector<double>& height, std::vector<double>* slope,
                       std::vector<double>* curvature) {
  const std::size_t n = static_cast<std::size_t>(grid.cells());
  slope->assign(n, std::nan(""));
  curvature->assign(n, std::nan(""));
  const int columns = grid.columns, rows = grid.rows;
  auto at = [&](int x, int y) {
    if (x < 0 || x >= columns || y < 0 || y >= rows) return std::nan("");
    return height[static_cast<std::size_t>(y) * columns + x];
  };
  // Derivative and second derivative along one axis from the two neighbours.
  auto axis = [](double before, double here, double after, double step, double* first, double* second) {
    const bool b = std::isfinite(before), a = std::isfinite(after);
    *second = b && a ? (after - 2 * here + before) / (step * step) : std::nan("");
    *first = b && a ? (after - before) / (2 * step) : a ? (after - here) / step : b ? (here - before) / step
                                                                                     : std::nan("");
  };
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < columns; ++x) {
      const double here = at(x, y);
      if (!std::isfinite(here)) continue;
      double gx, gy, cx, cy;
      axis(at(x - 1, y), here, at(x + 1, y), grid.dx, &gx, &cx);
      axis(at(x, y + 1), here, at(x, y - 1), grid.dy, &gy, &cy);  // row 0 at the top: north up
      const std::size_t i = static_cast<std::size_t>(y) * columns + x;
      if (std::isfinite(gx) || std::isfinite(gy)) {
        (*slope)[i] = std::hypot(std::isfinite(gx) ? gx : 0.0, std::isfinite(gy) ? gy : 0.0);
      }
      if (std::isfinite(cx) || std::isfinite(cy)) {
        (*curvature)[i] = std::fabs((std::isfinite(cx) ? cx : 0.0) + (std::isfinite(cy) ? cy : 0.0));
      }
    }
  }
}

double SigmaModel::At(double s, double c) const {
  return Interpolate(slope, sigma, s) * (curvature.empty() ? 1.0 : Interpolate(curvature, factor, c));
}

DodErrorModel FitDodErrorModel(const DodGrid& dod, std::vector<double>* sigma, const Execution& execution,
                               const std::string& where) {
  const std::size_t n = static_cast<std::size_t>(dod.layout.cells());
  DodErrorModel model;
  model.sigma_estimated = sigma->empty();
  // The stable cells' dz, and of them the inliers: within 4 NMAD of the median
  // (a change the stable terrain missed is not noise).
  std::vector<double> stable_dz;
  for (std::size_t i = 0; i < n; ++i) {
    if (dod.stable[i] && std::isfinite(dod.dz[i])) stable_dz.push_back(dod.dz[i]);
  }
  model.stable_median = Median(stable_dz);
  model.stable_nmad = stable_dz.empty() ? std::nan("") : Nmad(stable_dz);
  std::vector<uint8_t> inlier(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!dod.stable[i] || !std::isfinite(dod.dz[i])) continue;
    if (std::fabs(dod.dz[i] - model.stable_median) <= kInlierNmads * model.stable_nmad) {
      inlier[i] = 1;
      ++model.stable_cells;
    }
  }
  if (model.stable_cells < kMinStableCells) {
    throw InputError(where + ": only " + std::to_string(model.stable_cells) +
                     " stable cells with a DoD value, and the variogram error model needs at least " +
                     std::to_string(kMinStableCells) +
                     " (a larger stable area, or error_model: independent)");
  }
  if (model.sigma_estimated) {
    std::vector<double> slope, curvature;
    SlopeAndCurvature(dod.layout, dod.height, &slope, &curvature);
    std::vector<std::pair<double, double>> by_slope;
    for (std::size_t i = 0; i < n; ++i) {
      if (inlier[i] && std::isfinite(slope[i])) by_slope.emplace_back(slope[i], dod.dz[i]);
    }
    BinnedNmad(std::move(by_slope), kSlopeBins, &model.sigma_model.slope, &model.sigma_model.sigma);
    std::vector<std::pair<double, double>> by_curvature;
    for (std::size_t i = 0; i < n; ++i) {
      if (!inlier[i] || !std::isfinite(curvature[i])) continue;
      const double s = Interpolate(model.sigma_model.slope, model.sigma_model.sigma, slope[i]);
      if (s > 0) by_curvature.emplace_back(curvature[i], (dod.dz[i] - model.stable_median) / s);
    }
    BinnedNmad(std::move(by_curvature), kCurvatureBins, &model.sigma_model.curvature, &model.sigma_model.factor);
    sigma->assign(n, std::nan(""));
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(dod.dz[i])) continue;
      (*sigma)[i] = model.sigma_model.slope.empty() ? 0.0 : model.sigma_model.At(slope[i], curvature[i]);
    }
  }
  // The variogram of the standardized stable dz.
  std::vector<double> standard(n, std::nan(""));
  for (std::size_t i = 0; i < n; ++i) {
    if (inlier[i] && (*sigma)[i] > 0) standard[i] = (dod.dz[i] - model.stable_median) / (*sigma)[i];
  }
  model.empirical = SampleVariogram(dod.layout, standard, execution);
  const double step = std::min(dod.layout.dx, dod.layout.dy);
  const double longest = model.empirical.lag.empty() ? step : 2 * model.empirical.lag.back();
  model.variogram = FitVariogram(model.empirical, 0.5 * step, std::max(step, longest));
  return model;
}

}  // namespace surfreg

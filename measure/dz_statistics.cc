#include "measure/dz_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace surfreg {
namespace {

// The q-quantile (0..1) of `values`, linear between order statistics (as
// of the sorted values); reorders them. Selection, not a sort: linear.
double Quantile(std::vector<double>& values, double q) {
  const double position = q * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double t = position - static_cast<double>(below);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(below), values.end());
  const double low = values[below];
  const double high =
      above == below ? low : *std::min_element(values.begin() + static_cast<std::ptrdiff_t>(above), values.end());
  return low + t * (high - low);
}

}  // namespace

DzStatistics ComputeDzStatistics(const std::vector<double>& dz, const std::vector<bool>& keep,
                                 const Execution& execution) {
  std::vector<double> values;
  values.reserve(dz.size());
  for (std::size_t i = 0; i < dz.size(); ++i) {
    if (!keep.empty() && !keep[i]) continue;
    if (std::isfinite(dz[i])) values.push_back(dz[i]);
  }
  DzStatistics s;
  s.count = static_cast<int64_t>(values.size());
  if (values.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.mean = s.median = s.nmad = s.stddev = s.rmse = s.le90 = s.min = s.max = nan;
    return s;
  }
  // Mean and spread by Welford's update: no cancellation for large offsets.
  double mean = 0.0, m2 = 0.0, squares = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double delta = values[k] - mean;
    mean += delta / static_cast<double>(k + 1);
    m2 += delta * (values[k] - mean);
    squares += values[k] * values[k];
  }
  s.mean = mean;
  s.stddev = values.size() > 1 ? std::sqrt(m2 / static_cast<double>(values.size() - 1)) : 0.0;
  s.rmse = std::sqrt(squares / static_cast<double>(values.size()));
  const auto [lowest, highest] = std::minmax_element(values.begin(), values.end());
  s.min = *lowest;
  s.max = *highest;
  // |dz| in a buffer of its own, so that its selection may run beside the
  // median's and then the deviations'.
  std::vector<double> magnitudes(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) magnitudes[k] = std::fabs(values[k]);
  RunBoth(
      execution,
      [&] {
        s.median = Quantile(values, 0.5);
        for (double& v : values) v = std::fabs(v - s.median);  // deviations
        s.nmad = 1.4826 * Quantile(values, 0.5);
      },
      [&] { s.le90 = Quantile(magnitudes, 0.9); });
  return s;
}

std::string DzStatisticsLine(const DzStatistics& s, const std::string& units) {
  char line[320];
  std::snprintf(line, sizeof line,
                "n %lld, mean %.4g, median %.4g, NMAD %.4g, std %.4g, RMSE %.4g, LE90 %.4g %s",
                static_cast<long long>(s.count), s.mean, s.median, s.nmad, s.stddev, s.rmse, s.le90,
                units.c_str());
  return line;
}

}  // namespace surfreg

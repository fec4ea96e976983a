#pragma once
// Statistics of vertical differences dz, as terrain users compare
// co-registration tools by them (e.g. Höhle & Höhle 2009; Nuth & Kääb 2011):
// on stable terrain, after a good alignment, the median is near 0 and the
// NMAD (a robust standard deviation) near the noise of the surveys.
#include <cstdint>
#include <string>
#include <vector>

#include "measure/tasks.h"

namespace surfreg {

struct DzStatistics {
  int64_t count = 0;    // finite values used
  double mean = 0;
  double median = 0;
  double nmad = 0;      // 1.4826 · median(|dz − median|): σ for Gaussian dz
  double stddev = 0;    // sample standard deviation (n − 1)
  double rmse = 0;      // sqrt(mean(dz²))
  double le90 = 0;      // 90th percentile of |dz| (linear error at 90%)
  double min = 0, max = 0;
};

// Statistics of the finite values of dz for which `keep` is true (`keep`
// empty: all). NaN and infinite values are skipped (e.g. outside the
// overlap). With no value, count = 0 and every statistic is NaN.
// Runs by chunks on `execution`'s threads (the quantiles by an exact
// parallel selection): the same numbers for any thread count.
DzStatistics ComputeDzStatistics(const std::vector<double>& dz, const std::vector<bool>& keep = {},
                                 const Execution& execution = Execution{1});

// One line: "n 1234, mean 0.01, median 0.00, NMAD 0.05, std 0.06, RMSE ..."
std::string DzStatisticsLine(const DzStatistics& s, const std::string& units);

}  // namespace surfreg

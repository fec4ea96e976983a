#include "terrain/variogram.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace surfreg {
namespace {

// SplitMix64: a small generator whose sequence is the same on every
// platform, so that the sampled pairs (and the fit) are too.
struct Random {
  uint64_t state;
  uint64_t Next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
};

constexpr double kBinGrowth = 1.25;
constexpr int64_t kMinPairs = 30;
// The F statistic a richer variogram must reach (FitVariogram).
constexpr double kSignificance = 10;

// One bin's pairs: random valid cells (over all grids alike), a random
// offset whose length falls in [lo, hi) (uniform over the annulus' area,
// half a turn of directions: the variogram is symmetric), the partner in
// the same grid.
void SampleBin(const std::vector<GridValues>& grids,
               const std::vector<std::pair<int, int64_t>>& valid, double lo, double hi, int bin,
               int64_t pairs_per_bin, double* lag, double* gamma, int64_t* pairs) {
  Random random{0x5eed0000ULL + static_cast<uint64_t>(bin) * 0x100000001b3ULL};
  std::vector<double> squares;
  squares.reserve(static_cast<std::size_t>(pairs_per_bin));
  double distance_sum = 0;
  const int64_t attempts = 30 * pairs_per_bin;
  const double pi = std::acos(-1.0);
  for (int64_t a = 0; a < attempts && static_cast<int64_t>(squares.size()) < pairs_per_bin; ++a) {
    const auto& [which, anchor] = valid[random.Next() % valid.size()];
    const GridLayout& grid = grids[static_cast<std::size_t>(which)].grid;
    const std::vector<double>& values = *grids[static_cast<std::size_t>(which)].values;
    const double d = std::sqrt(lo * lo + random.Uniform() * (hi * hi - lo * lo));
    const double angle = random.Uniform() * pi;
    const long ox = std::lround(d * std::cos(angle) / grid.dx);
    const long oy = std::lround(d * std::sin(angle) / grid.dy);
    if (ox == 0 && oy == 0) continue;
    const double distance =
        std::hypot(static_cast<double>(ox) * grid.dx, static_cast<double>(oy) * grid.dy);
    if (distance < lo || distance >= hi) continue;
    const int64_t column = anchor % grid.columns + ox, row = anchor / grid.columns + oy;
    if (column < 0 || column >= grid.columns || row < 0 || row >= grid.rows) continue;
    const double other = values[static_cast<std::size_t>(row * grid.columns + column)];
    if (!std::isfinite(other)) continue;
    const double difference = values[static_cast<std::size_t>(anchor)] - other;
    squares.push_back(difference * difference);
    distance_sum += distance;
  }
  *pairs = static_cast<int64_t>(squares.size());
  if (*pairs < kMinPairs) return;
  double sum = 0;
  for (double square : squares) sum += square;
  *gamma = 0.5 * sum / static_cast<double>(*pairs);
  *lag = distance_sum / static_cast<double>(*pairs);
}

// 1 − spherical correlation at each bin's lag: the shape a sill multiplies.
std::vector<double> Shape(const std::vector<double>& lags, double range) {
  std::vector<double> shape(lags.size());
  for (std::size_t b = 0; b < lags.size(); ++b) shape[b] = 1 - SphericalCorrelation(lags[b], range);
  return shape;
}

struct Fit {
  double residual = std::numeric_limits<double>::infinity();
  double nugget = 0, sill_short = 0, sill_long = 0;
};

// Non-negative weighted least squares of y on the columns [1, short, long]
// (`long_shape` null: two columns) by trying every subset of active
// columns: three unknowns at most, so this is exact and cheap.
Fit SolveSills(const std::vector<double>& y, const std::vector<double>& w,
               const std::vector<double>& short_shape, const std::vector<double>* long_shape) {
  const int columns = long_shape ? 3 : 2;
  const std::size_t n = y.size();
  auto column = [&](int k, std::size_t b) {
    return k == 0 ? 1.0 : k == 1 ? short_shape[b] : (*long_shape)[b];
  };
  Fit best;
  for (int subset = 1; subset < (1 << columns); ++subset) {
    int active[3], m = 0;
    for (int k = 0; k < columns; ++k) {
      if (subset & (1 << k)) active[m++] = k;
    }
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d right = Eigen::Vector3d::Zero();
    for (std::size_t b = 0; b < n; ++b) {
      for (int i = 0; i < m; ++i) {
        right[i] += w[b] * column(active[i], b) * y[b];
        for (int j = 0; j < m; ++j)
          normal(i, j) += w[b] * column(active[i], b) * column(active[j], b);
      }
    }
    const Eigen::VectorXd beta = normal.topLeftCorner(m, m).ldlt().solve(right.head(m));
    if (!beta.allFinite() || (beta.array() < 0).any()) continue;
    double values[3] = {0, 0, 0};
    for (int i = 0; i < m; ++i) values[active[i]] = beta[i];
    double residual = 0;
    for (std::size_t b = 0; b < n; ++b) {
      double model = 0;
      for (int k = 0; k < columns; ++k) model += values[k] * column(k, b);
      residual += w[b] * (y[b] - model) * (y[b] - model);
    }
    if (residual < best.residual) best = {residual, values[0], values[1], values[2]};
  }
  return best;
}

}  // namespace

double SphericalCorrelation(double h, double range) {
  if (!(h > 0)) return 1;
  if (std::isinf(range)) return 1;
  if (!(range > 0) || h >= range) return 0;
  const double u = h / range;
  return 1 - 1.5 * u + 0.5 * u * u * u;
}

double Variogram::Gamma(double h) const {
  if (!(h > 0)) return 0;
  return nugget + sill[0] * (1 - SphericalCorrelation(h, range[0])) +
         sill[1] * (1 - SphericalCorrelation(h, range[1]));
}

double Variogram::Correlation(double h) const {
  if (!(h > 0)) return 1;
  const double total = Total();
  return total > 0 ? 1 - Gamma(h) / total : 0;
}

EmpiricalVariogram SampleVariogram(const GridLayout& grid, const std::vector<double>& values,
                                   const Execution& execution, int64_t pairs_per_bin) {
  return SampleVariogram(std::vector<GridValues>{{grid, &values}}, execution, pairs_per_bin);
}

EmpiricalVariogram SampleVariogram(const std::vector<GridValues>& grids, const Execution& execution,
                                   int64_t pairs_per_bin) {
  EmpiricalVariogram out;
  std::vector<std::pair<int, int64_t>> valid;
  double max_lag = 0, step = HUGE_VAL;
  for (std::size_t g = 0; g < grids.size(); ++g) {
    const GridLayout& grid = grids[g].grid;
    const std::vector<double>& values = *grids[g].values;
    int64_t column_min = grid.columns, column_max = -1, row_min = grid.rows, row_max = -1;
    for (int64_t cell = 0; cell < grid.cells(); ++cell) {
      if (!std::isfinite(values[static_cast<std::size_t>(cell)])) continue;
      valid.emplace_back(static_cast<int>(g), cell);
      const int64_t column = cell % grid.columns, row = cell / grid.columns;
      column_min = std::min(column_min, column), column_max = std::max(column_max, column);
      row_min = std::min(row_min, row), row_max = std::max(row_max, row);
    }
    if (column_max < 0) continue;
    step = std::min({step, grid.dx, grid.dy});
    max_lag =
        std::max(max_lag, 0.5 * std::hypot(static_cast<double>(column_max - column_min) * grid.dx,
                                           static_cast<double>(row_max - row_min) * grid.dy));
  }
  if (valid.size() < 2) return out;
  std::vector<double> edges = {0.75 * step};
  while (edges.back() < max_lag) edges.push_back(edges.back() * kBinGrowth);
  const int bins = static_cast<int>(edges.size()) - 1;
  if (bins < 1) return out;
  std::vector<double> lag(static_cast<std::size_t>(bins), 0), gamma(lag.size(), 0);
  std::vector<int64_t> pairs(lag.size(), 0);
  ForEachChunk(execution, bins, std::min(bins, kMaxChunks), [&](int, int64_t begin, int64_t end) {
    for (int64_t b = begin; b < end; ++b) {
      const std::size_t k = static_cast<std::size_t>(b);
      SampleBin(grids, valid, edges[k], edges[k + 1], static_cast<int>(b), pairs_per_bin, &lag[k],
                &gamma[k], &pairs[k]);
    }
  });
  for (std::size_t b = 0; b < lag.size(); ++b) {
    if (pairs[b] < kMinPairs) continue;
    out.lag.push_back(lag[b]);
    out.gamma.push_back(gamma[b]);
    out.pairs.push_back(pairs[b]);
  }
  return out;
}

Variogram FitVariogram(const EmpiricalVariogram& empirical, double min_range, double max_range) {
  std::vector<double> lags, y, w;
  for (std::size_t b = 0; b < empirical.lag.size(); ++b) {
    if (!(empirical.gamma[b] > 0)) continue;
    lags.push_back(empirical.lag[b]);
    y.push_back(empirical.gamma[b]);
    w.push_back(static_cast<double>(empirical.pairs[b]) /
                (empirical.gamma[b] * empirical.gamma[b]));
  }
  Variogram out;
  // No correlation: the nugget is the weighted mean.
  double weight = 0, weighted = 0;
  for (std::size_t b = 0; b < y.size(); ++b) weight += w[b], weighted += w[b] * y[b];
  out.nugget = weight > 0 ? weighted / weight : 0.0;
  if (lags.size() < 3) return out;
  double flat = 0;
  for (std::size_t b = 0; b < y.size(); ++b)
    flat += w[b] * (y[b] - out.nugget) * (y[b] - out.nugget);
  // Ranges on a grid growing by 8%, then refined in 1% steps about the best.
  constexpr double kGrowth = 1.08;
  std::vector<double> ranges;
  for (double r = min_range; r <= max_range * (1 + 1e-12); r *= kGrowth) ranges.push_back(r);
  std::vector<std::vector<double>> shapes;
  for (double r : ranges) shapes.push_back(Shape(lags, r));
  // One spherical model.
  Fit one;
  double one_range = ranges.front();
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const Fit fit = SolveSills(y, w, shapes[i], nullptr);
    if (fit.residual < one.residual * (1 - 1e-12)) one = fit, one_range = ranges[i];
  }
  for (int a = -8; a <= 8; ++a) {
    const double r = one_range * std::pow(kGrowth, a / 8.0);
    const Fit fit = SolveSills(y, w, Shape(lags, r), nullptr);
    if (fit.residual < one.residual * (1 - 1e-12)) one = fit, one_range = r;
  }
  // Two: every pair short < long.
  Fit two;
  double best_short = ranges.front(), best_long = ranges.front();
  auto consider = [&](double r_short, double r_long, const std::vector<double>& s,
                      const std::vector<double>& l) {
    const Fit fit = SolveSills(y, w, s, &l);
    if (fit.residual < two.residual * (1 - 1e-12))
      two = fit, best_short = r_short, best_long = r_long;
  };
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    for (std::size_t j = i + 1; j < ranges.size(); ++j)
      consider(ranges[i], ranges[j], shapes[i], shapes[j]);
  }
  const double coarse_short = best_short, coarse_long = best_long;
  for (int a = -8; a <= 8; ++a) {
    const double r_short = coarse_short * std::pow(kGrowth, a / 8.0);
    const std::vector<double> s = Shape(lags, r_short);
    for (int b = -8; b <= 8; ++b) {
      const double r_long = coarse_long * std::pow(kGrowth, b / 8.0);
      if (r_long > r_short) consider(r_short, r_long, s, Shape(lags, r_long));
    }
  }
  // A model with more terms only where the data ask for it: an F test of
  // the weighted residuals (1, 3 and 5 parameters), at a level the bins'
  // noise (their pairs are not independent) does not reach by chance. A
  // small sill fitted to noise at a long range would swell every budget.
  const double n = static_cast<double>(lags.size());
  auto significant = [&](double simple, double rich, double added, double parameters) {
    if (n - parameters < 1) return false;
    if (!(rich > 0)) return simple > 0;
    return (simple - rich) / added / (rich / (n - parameters)) > kSignificance;
  };
  const bool use_one = one.sill_short > 0 && significant(flat, one.residual, 2, 3);
  const bool use_two = use_one && two.sill_short > 0 && two.sill_long > 0 &&
                       significant(one.residual, two.residual, 2, 5);
  if (use_two) {
    out.nugget = two.nugget;
    out.sill = {two.sill_short, two.sill_long};
    out.range = {best_short, best_long};
  } else if (use_one) {
    out.nugget = one.nugget;
    out.sill = {0.0, one.sill_short};
    out.range = {0.0, one_range};
  }
  return out;
}

}  // namespace surfreg

#include "terrain/spatial_budget.h"

#include <algorithm>
#include <cmath>

namespace surfreg {
namespace {

struct Offset {
  int dx, dy;
  double kernel;  // K at the offset's length, times 2 for a pair counted once for both directions
};

// Offsets of the half plane (dy > 0, or dy = 0 and dx >= 0) shorter than
// `support`, with their kernel values.
std::vector<Offset> HalfPlaneOffsets(const GridLayout& grid, double support,
                                     double (*kernel)(double, const void*), const void* data) {
  std::vector<Offset> offsets;
  const int reach_x = static_cast<int>(std::min<double>(grid.columns - 1, std::floor(support / grid.dx)));
  const int reach_y = static_cast<int>(std::min<double>(grid.rows - 1, std::floor(support / grid.dy)));
  for (int dy = 0; dy <= reach_y; ++dy) {
    for (int dx = dy == 0 ? 0 : -reach_x; dx <= reach_x; ++dx) {
      const double d = std::hypot(dx * grid.dx, dy * grid.dy);
      if (d > support) continue;
      const double k = kernel(d, data);
      if (k == 0) continue;
      offsets.push_back({dx, dy, (dx == 0 && dy == 0) ? k : 2 * k});
    }
  }
  return offsets;
}

int64_t HalfPlaneOffsetCount(const GridLayout& grid, double support) {
  const double rx = std::min<double>(grid.columns, support / grid.dx + 1);
  const double ry = std::min<double>(grid.rows, support / grid.dy + 1);
  return static_cast<int64_t>(std::min(2 * rx * ry, 1.6 * rx * ry + rx + ry));
}

double ExactQuadraticForm(const GridLayout& grid, const std::vector<double>& w,
                          double (*kernel)(double, const void*), const void* data, double support,
                          const Execution& execution) {
  const std::vector<Offset> offsets = HalfPlaneOffsets(grid, support, kernel, data);
  const int64_t n = static_cast<int64_t>(offsets.size());
  const int chunks = ChunksFor(n, 8);
  std::vector<double> sums(static_cast<std::size_t>(chunks), 0.0);
  const int columns = grid.columns, rows = grid.rows;
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    double chunk = 0;
    for (int64_t k = begin; k < end; ++k) {
      const Offset& o = offsets[static_cast<std::size_t>(k)];
      const int x0 = std::max(0, -o.dx), x1 = std::min(columns, columns - o.dx);
      double lagged = 0;
      for (int y = 0; y + o.dy < rows; ++y) {
        const double* a = w.data() + static_cast<std::size_t>(y) * columns;
        const double* b = w.data() + static_cast<std::size_t>(y + o.dy) * columns + o.dx;
        double row = 0;
        for (int x = x0; x < x1; ++x) row += a[x] * b[x];
        lagged += row;
      }
      chunk += o.kernel * lagged;
    }
    sums[static_cast<std::size_t>(c)] = chunk;
  });
  double total = 0;
  for (double s : sums) total += s;
  return total;
}

// A weighted sum of two spherical correlations and their products:
// linear[k] S_k + square[k] S_k² + cross S_0 S_1.
struct SphericalMix {
  double range[2] = {0, 0};
  double linear[2] = {0, 0}, square[2] = {0, 0}, cross = 0;
};

double MixKernel(double h, const void* data) {
  const SphericalMix& m = *static_cast<const SphericalMix*>(data);
  const double s0 = SphericalCorrelation(h, m.range[0]), s1 = SphericalCorrelation(h, m.range[1]);
  return m.linear[0] * s0 + m.linear[1] * s1 + m.square[0] * s0 * s0 + m.square[1] * s1 * s1 + m.cross * s0 * s1;
}

double NormalDensity(double x) { return 0.3989422804014327 * std::exp(-0.5 * x * x); }
double NormalTail(double x) { return 0.5 * std::erfc(x / std::sqrt(2.0)); }  // P(Z > x)

bool AllZero(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return x == 0; });
}

}  // namespace

double KernelQuadraticForm(const GridLayout& grid, const std::vector<double>& w,
                           double (*kernel)(double, const void*), const void* kernel_data, double support,
                           const Execution& execution, double budget, int* block) {
  const double diagonal = std::hypot(grid.columns * grid.dx, grid.rows * grid.dy);
  support = std::min(support, diagonal);
  int b = 1;
  for (;; ++b) {
    GridLayout coarse{(grid.columns + b - 1) / b, (grid.rows + b - 1) / b, grid.dx * b, grid.dy * b};
    const double cost = static_cast<double>(coarse.cells()) * static_cast<double>(HalfPlaneOffsetCount(coarse, support));
    if (cost <= budget || (coarse.columns <= 1 && coarse.rows <= 1)) break;
  }
  if (block) *block = b;
  if (b == 1) return ExactQuadraticForm(grid, w, kernel, kernel_data, support, execution);
  GridLayout coarse{(grid.columns + b - 1) / b, (grid.rows + b - 1) / b, grid.dx * b, grid.dy * b};
  std::vector<double> sums(static_cast<std::size_t>(coarse.cells()), 0.0);
  for (int y = 0; y < grid.rows; ++y) {
    const std::size_t row = static_cast<std::size_t>(y / b) * static_cast<std::size_t>(coarse.columns);
    for (int x = 0; x < grid.columns; ++x) {
      sums[row + static_cast<std::size_t>(x / b)] += w[static_cast<std::size_t>(y) * grid.columns + x];
    }
  }
  return ExactQuadraticForm(coarse, sums, kernel, kernel_data, support, execution);
}

HermiteTerms CellHermiteTerms(double dz, double sigma, double threshold) {
  HermiteTerms t;
  if (!(sigma > 0)) return t;
  const double l = std::max(0.0, threshold);
  const double mu = std::fabs(dz) > l ? dz : 0.0;
  const double a = (l - mu) / sigma, b = (-l - mu) / sigma;
  const double upper = NormalTail(a), lower = NormalTail(-b);  // P(X > L), P(X < −L)
  const double pa = NormalDensity(a), pb = NormalDensity(b);
  const double second = mu * mu + sigma * sigma;
  const double fill_mean = mu * upper + sigma * pa;
  const double fill_square = second * upper + sigma * pa * (mu + l);
  t.fill_c1 = l * pa + sigma * upper;
  const double cut_mean = -(mu * lower - sigma * pb);
  const double cut_square = second * lower - sigma * pb * (mu - l);
  t.cut_c1 = -(l * pb + sigma * lower);
  const double net_mean = fill_mean - cut_mean, net_square = fill_square + cut_square;
  t.net_c1 = t.fill_c1 - t.cut_c1;
  auto rest = [](double square, double mean, double c1) { return std::max(0.0, square - mean * mean - c1 * c1); };
  t.fill_rest = rest(fill_square, fill_mean, t.fill_c1);
  t.cut_rest = rest(cut_square, cut_mean, t.cut_c1);
  t.net_rest = rest(net_square, net_mean, t.net_c1);
  return t;
}

SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const std::vector<double>& dz,
                                   const std::vector<double>& sigma, const std::vector<double>& threshold,
                                   const std::vector<double>& area, const Variogram& variogram,
                                   const Execution& execution, double budget) {
  const std::size_t n = static_cast<std::size_t>(grid.cells());
  // u = a c₁ and v = a √R per cell, for fill, cut and net.
  std::vector<double> u[3], v[3];
  for (int k = 0; k < 3; ++k) u[k].assign(n, 0.0), v[k].assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = threshold.empty() ? 0.0 : threshold[i];
    if (!std::isfinite(dz[i]) || !std::isfinite(sigma[i]) || !std::isfinite(area[i]) || !std::isfinite(t)) continue;
    const HermiteTerms h = CellHermiteTerms(dz[i], sigma[i], t);
    u[0][i] = area[i] * h.fill_c1, v[0][i] = area[i] * std::sqrt(h.fill_rest);
    u[1][i] = area[i] * h.cut_c1, v[1][i] = area[i] * std::sqrt(h.cut_rest);
    u[2][i] = area[i] * h.net_c1, v[2][i] = area[i] * std::sqrt(h.net_rest);
  }
  // ρ = p₀ δ + p₁ S₁ + p₂ S₂; ρ² = (1 − (p₁ + p₂)²) δ + (p₁ S₁ + p₂ S₂)².
  const double total = variogram.Total();
  double p[3] = {1, 0, 0};
  if (total > 0) p[0] = variogram.nugget / total, p[1] = variogram.sill[0] / total, p[2] = variogram.sill[1] / total;
  const double r[2] = {variogram.range[0], variogram.range[1]};
  SphericalMix linear_short, linear_long, square_short, square_long;
  linear_short.range[0] = linear_long.range[0] = square_short.range[0] = square_long.range[0] = r[0];
  linear_short.range[1] = linear_long.range[1] = square_short.range[1] = square_long.range[1] = r[1];
  linear_short.linear[0] = p[1];
  linear_long.linear[1] = p[2];
  square_short.square[0] = p[1] * p[1];
  square_short.cross = 2 * p[1] * p[2];
  square_long.square[1] = p[2] * p[2];
  const double short_support = std::min(r[0], r[1]);  // S₁ S₂ lives within the shorter range
  SpatialSigma out;
  double variance[3];
  for (int k = 0; k < 3; ++k) {
    double linear = 0, square = 0, diagonal_u = 0, diagonal_v = 0;
    for (std::size_t i = 0; i < n; ++i) diagonal_u += u[k][i] * u[k][i], diagonal_v += v[k][i] * v[k][i];
    linear += p[0] * diagonal_u;
    int block = 1;
    auto form = [&](const std::vector<double>& w, const SphericalMix& mix, double support) {
      if (!(support > 0)) return 0.0;
      int b = 1;
      const double value = KernelQuadraticForm(grid, w, MixKernel, &mix, support, execution, budget, &b);
      block = std::max(block, b);
      return value;
    };
    if (p[1] > 0) linear += form(u[k], linear_short, r[0]);
    if (p[2] > 0) linear += form(u[k], linear_long, r[1]);
    if (!AllZero(v[k])) {
      square += (1 - (p[1] + p[2]) * (p[1] + p[2])) * diagonal_v;
      if (p[1] > 0) square += form(v[k], square_short, short_support);
      if (p[2] > 0) square += form(v[k], square_long, r[1]);
    }
    variance[k] = std::max(0.0, linear + square);
    out.block = std::max(out.block, block);
  }
  out.fill = std::sqrt(variance[0]);
  out.cut = std::sqrt(variance[1]);
  out.net = std::sqrt(variance[2]);
  return out;
}

}  // namespace surfreg

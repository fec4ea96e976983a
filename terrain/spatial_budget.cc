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

// Σ over the first `core` rows y of `w` (a buffer of `buffer` rows of
// `columns`) and every offset o of Σ_x w(y, x) w(y + o.dy, x + o.dx) K(o),
// partners beyond the buffer left out. Offsets in chunks fixed by their
// number: the same sum for any number of threads.
double BandQuadraticForm(const std::vector<double>& w, int columns, int core, int buffer,
                         const std::vector<Offset>& offsets, const Execution& execution) {
  const int64_t n = static_cast<int64_t>(offsets.size());
  if (n == 0 || core == 0) return 0;
  const int chunks = ChunksFor(n, 8);
  std::vector<double> sums(static_cast<std::size_t>(chunks), 0.0);
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    double chunk = 0;
    for (int64_t k = begin; k < end; ++k) {
      const Offset& o = offsets[static_cast<std::size_t>(k)];
      const int x0 = std::max(0, -o.dx), x1 = std::min(columns, columns - o.dx);
      double lagged = 0;
      for (int y = 0; y < core && y + o.dy < buffer; ++y) {
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

// The block side b for a kernel of `support` on `grid`: 1 (exact) while
// every pair within the support costs at most `budget` multiply-adds.
int ChooseBlock(const GridLayout& grid, double support, double budget) {
  for (int b = 1;; ++b) {
    GridLayout coarse{(grid.columns + b - 1) / b, (grid.rows + b - 1) / b, grid.dx * b, grid.dy * b};
    const double cost = static_cast<double>(coarse.cells()) * static_cast<double>(HalfPlaneOffsetCount(coarse, support));
    if (cost <= budget || (coarse.columns <= 1 && coarse.rows <= 1)) return b;
  }
}

GridLayout Coarse(const GridLayout& grid, int b) {
  return {(grid.columns + b - 1) / b, (grid.rows + b - 1) / b, grid.dx * b, grid.dy * b};
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


}  // namespace

double KernelQuadraticForm(const GridLayout& grid, const std::vector<double>& w,
                           double (*kernel)(double, const void*), const void* kernel_data, double support,
                           const Execution& execution, double budget, int* block) {
  support = std::min(support, std::hypot(grid.columns * grid.dx, grid.rows * grid.dy));
  const int b = ChooseBlock(grid, support, budget);
  if (block) *block = b;
  if (b == 1) {
    return BandQuadraticForm(w, grid.columns, grid.rows, grid.rows, HalfPlaneOffsets(grid, support, kernel, kernel_data),
                             execution);
  }
  const GridLayout coarse = Coarse(grid, b);
  std::vector<double> sums(static_cast<std::size_t>(coarse.cells()), 0.0);
  for (int y = 0; y < grid.rows; ++y) {
    const std::size_t row = static_cast<std::size_t>(y / b) * static_cast<std::size_t>(coarse.columns);
    for (int x = 0; x < grid.columns; ++x) {
      sums[row + static_cast<std::size_t>(x / b)] += w[static_cast<std::size_t>(y) * grid.columns + x];
    }
  }
  return BandQuadraticForm(sums, coarse.columns, coarse.rows, coarse.rows,
                           HalfPlaneOffsets(coarse, support, kernel, kernel_data), execution);
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

int PropagationBandRows(const GridLayout& grid) {
  return std::max(8, (1 << 20) / std::max(1, grid.columns));
}

SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const BudgetRowReader& read, const Variogram& variogram,
                                   const Execution& execution, double budget) {
  // ρ = p₀ δ + p₁ S₁ + p₂ S₂; ρ² = (1 − (p₁ + p₂)²) δ + (p₁ S₁ + p₂ S₂)².
  const double total = variogram.Total();
  double p[3] = {1, 0, 0};
  if (total > 0) p[0] = variogram.nugget / total, p[1] = variogram.sill[0] / total, p[2] = variogram.sill[1] / total;
  const double diagonal = std::hypot(grid.columns * grid.dx, grid.rows * grid.dy);
  const double r[2] = {std::min(variogram.range[0], diagonal), std::min(variogram.range[1], diagonal)};
  // The kernel passes: on u = a c₁ (linear) or v = a √R (square), each with its own block.
  struct Pass {
    bool square = false;
    SphericalMix mix;
    double support = 0;
    int block = 1;
    GridLayout coarse;
    std::vector<Offset> offsets;
    std::vector<double> sums[3];  // per budget, the coarse blocks' weights (block > 1)
    double value[3] = {0, 0, 0};
  };
  std::vector<Pass> passes;
  auto add = [&](bool square, SphericalMix mix, double support) {
    mix.range[0] = variogram.range[0], mix.range[1] = variogram.range[1];
    Pass pass;
    pass.square = square, pass.mix = mix, pass.support = support;
    pass.block = ChooseBlock(grid, support, budget);
    pass.coarse = Coarse(grid, pass.block);
    pass.offsets = HalfPlaneOffsets(pass.coarse, support, MixKernel, &pass.mix);
    if (pass.block > 1) {
      for (auto& s : pass.sums) s.assign(static_cast<std::size_t>(pass.coarse.cells()), 0.0);
    }
    passes.push_back(std::move(pass));
  };
  if (p[1] > 0) {
    SphericalMix linear, square;
    linear.linear[0] = p[1];
    square.square[0] = p[1] * p[1];
    square.cross = 2 * p[1] * p[2];
    add(false, linear, r[0]);
    add(true, square, r[0]);  // S₁ S₂ lives within the shorter range
  }
  if (p[2] > 0) {
    SphericalMix linear, square;
    linear.linear[1] = p[2];
    square.square[1] = p[2] * p[2];
    add(false, linear, r[1]);
    add(true, square, r[1]);
  }
  int reach = 0;  // rows below a band that exact passes pair it with
  for (const Pass& pass : passes) {
    if (pass.block == 1) reach = std::max(reach, static_cast<int>(std::min<double>(grid.rows - 1, pass.support / grid.dy)));
  }
  const int band = PropagationBandRows(grid);
  const int columns = grid.columns;
  double diagonal_u[3] = {0, 0, 0}, diagonal_v[3] = {0, 0, 0};
  BudgetRows rows;
  std::vector<double> u[3], v[3];
  for (int y0 = 0; y0 < grid.rows; y0 += band) {
    const int y1 = std::min(grid.rows, y0 + band), end = std::min(grid.rows, y1 + reach);
    const int core = y1 - y0, buffer = end - y0;
    read(y0, end, core, &rows);
    const std::size_t n = static_cast<std::size_t>(buffer) * columns;
    for (int k = 0; k < 3; ++k) u[k].assign(n, 0.0), v[k].assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = rows.threshold[i];
      if (!std::isfinite(rows.dz[i]) || !std::isfinite(rows.sigma[i]) || !std::isfinite(rows.area[i]) ||
          !std::isfinite(t)) {
        continue;
      }
      const HermiteTerms h = CellHermiteTerms(rows.dz[i], rows.sigma[i], t);
      const double a = rows.area[i];
      u[0][i] = a * h.fill_c1, v[0][i] = a * std::sqrt(h.fill_rest);
      u[1][i] = a * h.cut_c1, v[1][i] = a * std::sqrt(h.cut_rest);
      u[2][i] = a * h.net_c1, v[2][i] = a * std::sqrt(h.net_rest);
    }
    const std::size_t core_cells = static_cast<std::size_t>(core) * columns;
    for (int k = 0; k < 3; ++k) {
      for (std::size_t i = 0; i < core_cells; ++i) diagonal_u[k] += u[k][i] * u[k][i], diagonal_v[k] += v[k][i] * v[k][i];
    }
    for (Pass& pass : passes) {
      for (int k = 0; k < 3; ++k) {
        const std::vector<double>& w = pass.square ? v[k] : u[k];
        if (pass.block == 1) {
          pass.value[k] += BandQuadraticForm(w, columns, core, buffer, pass.offsets, execution);
          continue;
        }
        const int b = pass.block;
        for (int y = 0; y < core; ++y) {
          const std::size_t row = static_cast<std::size_t>((y0 + y) / b) * static_cast<std::size_t>(pass.coarse.columns);
          for (int x = 0; x < columns; ++x) pass.sums[k][row + static_cast<std::size_t>(x / b)] += w[static_cast<std::size_t>(y) * columns + x];
        }
      }
    }
  }
  SpatialSigma out;
  double variance[3];
  for (int k = 0; k < 3; ++k) {
    double linear = p[0] * diagonal_u[k], square = (1 - (p[1] + p[2]) * (p[1] + p[2])) * diagonal_v[k];
    for (Pass& pass : passes) {
      if (pass.block > 1) {
        pass.value[k] = BandQuadraticForm(pass.sums[k], pass.coarse.columns, pass.coarse.rows, pass.coarse.rows,
                                          pass.offsets, execution);
      }
      (pass.square ? square : linear) += pass.value[k];
      out.block = std::max(out.block, pass.block);
    }
    variance[k] = std::max(0.0, linear + square);
  }
  out.fill = std::sqrt(variance[0]);
  out.cut = std::sqrt(variance[1]);
  out.net = std::sqrt(variance[2]);
  return out;
}

SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const std::vector<double>& dz,
                                   const std::vector<double>& sigma, const std::vector<double>& threshold,
                                   const std::vector<double>& area, const Variogram& variogram,
                                   const Execution& execution, double budget) {
  const BudgetRowReader read = [&](int row0, int row1, int, BudgetRows* rows) {
    const auto slice = [&](const std::vector<double>& all, std::vector<double>* part) {
      part->assign(all.begin() + static_cast<std::ptrdiff_t>(row0) * grid.columns,
                   all.begin() + static_cast<std::ptrdiff_t>(row1) * grid.columns);
    };
    slice(dz, &rows->dz), slice(sigma, &rows->sigma), slice(threshold, &rows->threshold), slice(area, &rows->area);
  };
  return PropagateSpatialSigma(grid, read, variogram, execution, budget);
}

}  // namespace surfreg

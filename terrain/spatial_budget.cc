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
  const int reach_x =
      static_cast<int>(std::min<double>(grid.columns - 1, std::floor(support / grid.dx)));
  const int reach_y =
      static_cast<int>(std::min<double>(grid.rows - 1, std::floor(support / grid.dy)));
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
    GridLayout coarse{(grid.columns + b - 1) / b, (grid.rows + b - 1) / b, grid.dx * b,
                      grid.dy * b};
    const double cost = static_cast<double>(coarse.cells()) *
                        static_cast<double>(HalfPlaneOffsetCount(coarse, support));
    if (cost <= budget || (coarse.columns <= 1 && coarse.rows <= 1)) return b;
  }
}

GridLayout Coarse(const GridLayout& grid, int b) {
  return {(grid.columns + b - 1) / b, (grid.rows + b - 1) / b, grid.dx * b, grid.dy * b};
}

// (p₁ S₁ + p₂ S₂)^power split in two: the terms with S₁ (zero beyond the
// short range) and (p₂ S₂)^power (zero beyond the long one).
struct SphericalPower {
  double range[2] = {0, 0}, p[2] = {0, 0};
  int power = 1;
  bool long_part = false;
};

double PowerKernel(double h, const void* data) {
  const SphericalPower& m = *static_cast<const SphericalPower*>(data);
  const double both =
      m.p[0] * SphericalCorrelation(h, m.range[0]) + m.p[1] * SphericalCorrelation(h, m.range[1]);
  const double long_only = std::pow(m.p[1] * SphericalCorrelation(h, m.range[1]), m.power);
  return m.long_part ? long_only : std::pow(both, m.power) - long_only;
}

double NormalDensity(double x) { return 0.3989422804014327 * std::exp(-0.5 * x * x); }
double NormalTail(double x) { return 0.5 * std::erfc(x / std::sqrt(2.0)); }  // P(Z > x)

}  // namespace

double KernelQuadraticForm(const GridLayout& grid, const std::vector<double>& w,
                           double (*kernel)(double, const void*), const void* kernel_data,
                           double support, const Execution& execution, double budget, int* block) {
  support = std::min(support, std::hypot(grid.columns * grid.dx, grid.rows * grid.dy));
  const int b = ChooseBlock(grid, support, budget);
  if (block) *block = b;
  if (b == 1) {
    return BandQuadraticForm(w, grid.columns, grid.rows, grid.rows,
                             HalfPlaneOffsets(grid, support, kernel, kernel_data), execution);
  }
  const GridLayout coarse = Coarse(grid, b);
  std::vector<double> sums(static_cast<std::size_t>(coarse.cells()), 0.0);
  for (int y = 0; y < grid.rows; ++y) {
    const std::size_t row =
        static_cast<std::size_t>(y / b) * static_cast<std::size_t>(coarse.columns);
    for (int x = 0; x < grid.columns; ++x) {
      sums[row + static_cast<std::size_t>(x / b)] +=
          w[static_cast<std::size_t>(y) * grid.columns + x];
    }
  }
  return BandQuadraticForm(sums, coarse.columns, coarse.rows, coarse.rows,
                           HalfPlaneOffsets(coarse, support, kernel, kernel_data), execution);
}

HermiteTerms CellHermiteTerms(double dz, double sigma, double threshold, bool noise) {
  HermiteTerms t;
  if (!(sigma > 0)) return t;
  const double l = std::max(0.0, threshold);
  const double mu = !noise && std::fabs(dz) > l ? dz : 0.0;
  const double a = (l - mu) / sigma, b = (-l - mu) / sigma;  // X > L: Z > a; X < −L: Z < b
  const double upper = NormalTail(a), lower = NormalTail(-b);
  const double pa = NormalDensity(a), pb = NormalDensity(b);
  const double second = mu * mu + sigma * sigma;
  // E g, E g², c₁ and c₂ of X 1(X > L) and of −X 1(X < −L), in closed form.
  const double mean[2] = {mu * upper + sigma * pa, -(mu * lower - sigma * pb)};
  const double square[2] = {second * upper + sigma * pa * (mu + l),
                            second * lower - sigma * pb * (mu - l)};
  const double c1[2] = {l * pa + sigma * upper, -(l * pb + sigma * lower)};
  const double c2[2] = {pa * (a * l + sigma), pb * (sigma - b * l)};
  auto rest = [](double variance, double first, double second_term) {
    return std::max(0.0, variance - first * first - 0.5 * second_term * second_term);
  };
  for (int k = 0; k < 2; ++k) {
    t.c1[k] = c1[k], t.c2[k] = c2[k];
    t.rest[k] = rest(square[k] - mean[k] * mean[k], c1[k], c2[k]);
  }
  // net = fill − cut; the two are never both non-zero: E net² = E fill² + E cut².
  const double net_mean = mean[0] - mean[1];
  t.c1[2] = c1[0] - c1[1], t.c2[2] = c2[0] - c2[1];
  t.rest[2] = rest(square[0] + square[1] - net_mean * net_mean, t.c1[2], t.c2[2]);
  return t;
}

int PropagationBandRows(const GridLayout& grid) {
  return std::max(8, (1 << 20) / std::max(1, grid.columns));
}

SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const BudgetRowReader& read,
                                   const Variogram& variogram, const Execution& execution,
                                   double budget) {
  // ρ = p₀ δ + p₁ S₁ + p₂ S₂ and its powers: ρ^k = (1 − (p₁ + p₂)^k) δ + (p₁ S₁ + p₂ S₂)^k.
  const double total = variogram.Total();
  double p[3] = {1, 0, 0};
  if (total > 0)
    p[0] = variogram.nugget / total, p[1] = variogram.sill[0] / total,
    p[2] = variogram.sill[1] / total;
  const double diagonal = std::hypot(grid.columns * grid.dx, grid.rows * grid.dy);
  const double r[2] = {std::min(variogram.range[0], diagonal),
                       std::min(variogram.range[1], diagonal)};
  constexpr int kPowers = 3;
  // The kernel passes: the weights of one power (w_k = a c₁, a c₂ / √2, a √R)
  // with the short or the long part of ρ^k, each with its own block.
  struct Pass {
    SphericalPower kernel;
    double support = 0;
    int block = 1;
    GridLayout coarse;
    std::vector<Offset> offsets;
    std::vector<double> sums[3];  // per budget, the coarse blocks' weights (block > 1)
    double value[3] = {0, 0, 0};
  };
  std::vector<Pass> passes;
  for (int power = 1; power <= kPowers; ++power) {
    for (int part = 0; part < 2; ++part) {
      if (!(p[1 + part] > 0) || !(r[part] > 0)) continue;
      Pass pass;
      pass.kernel.range[0] = variogram.range[0], pass.kernel.range[1] = variogram.range[1];
      pass.kernel.p[0] = p[1], pass.kernel.p[1] = p[2];
      pass.kernel.power = power, pass.kernel.long_part = part == 1;
      pass.support = r[part];
      pass.block = ChooseBlock(grid, pass.support, budget);
      pass.coarse = Coarse(grid, pass.block);
      passes.push_back(std::move(pass));
    }
  }
  for (Pass& pass : passes) {  // the kernel's address is final now
    pass.offsets = HalfPlaneOffsets(pass.coarse, pass.support, PowerKernel, &pass.kernel);
    if (pass.block > 1) {
      for (auto& s : pass.sums) s.assign(static_cast<std::size_t>(pass.coarse.cells()), 0.0);
    }
  }
  int reach = 0;  // rows below a band that exact passes pair it with
  for (const Pass& pass : passes) {
    if (pass.block == 1)
      reach = std::max(reach,
                       static_cast<int>(std::min<double>(grid.rows - 1, pass.support / grid.dy)));
  }
  const int band = PropagationBandRows(grid);
  const int columns = grid.columns;
  double diagonal_sum[kPowers][3] = {};
  BudgetRows rows;
  std::vector<double> w[kPowers][3];
  for (int y0 = 0; y0 < grid.rows; y0 += band) {
    const int y1 = std::min(grid.rows, y0 + band), end = std::min(grid.rows, y1 + reach);
    const int core = y1 - y0, buffer = end - y0;
    read(y0, end, core, &rows);
    const std::size_t n = static_cast<std::size_t>(buffer) * columns;
    for (auto& power : w) {
      for (auto& k : power) k.assign(n, 0.0);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double t = rows.threshold[i];
      if (!std::isfinite(rows.dz[i]) || !std::isfinite(rows.sigma[i]) ||
          !std::isfinite(rows.area[i]) || !std::isfinite(t)) {
        continue;
      }
      const HermiteTerms h =
          CellHermiteTerms(rows.dz[i], rows.sigma[i], t, !rows.noise.empty() && rows.noise[i]);
      const double a = rows.area[i];
      for (int k = 0; k < 3; ++k) {
        w[0][k][i] = a * h.c1[k];
        w[1][k][i] = a * h.c2[k] * std::sqrt(0.5);
        w[2][k][i] = a * std::sqrt(h.rest[k]);
      }
    }
    const std::size_t core_cells = static_cast<std::size_t>(core) * columns;
    for (int power = 0; power < kPowers; ++power) {
      for (int k = 0; k < 3; ++k) {
        for (std::size_t i = 0; i < core_cells; ++i)
          diagonal_sum[power][k] += w[power][k][i] * w[power][k][i];
      }
    }
    for (Pass& pass : passes) {
      for (int k = 0; k < 3; ++k) {
        const std::vector<double>& weights = w[pass.kernel.power - 1][k];
        if (pass.block == 1) {
          pass.value[k] +=
              BandQuadraticForm(weights, columns, core, buffer, pass.offsets, execution);
          continue;
        }
        const int b = pass.block;
        for (int y = 0; y < core; ++y) {
          const std::size_t row = static_cast<std::size_t>((y0 + y) / b) *
                                  static_cast<std::size_t>(pass.coarse.columns);
          for (int x = 0; x < columns; ++x) {
            pass.sums[k][row + static_cast<std::size_t>(x / b)] +=
                weights[static_cast<std::size_t>(y) * columns + x];
          }
        }
      }
    }
  }
  SpatialSigma out;
  double variance[3];
  for (int k = 0; k < 3; ++k) {
    variance[k] = 0;
    for (int power = 1; power <= kPowers; ++power) {
      variance[k] += (1 - std::pow(p[1] + p[2], power)) * diagonal_sum[power - 1][k];
    }
    for (Pass& pass : passes) {
      if (pass.block > 1) {
        pass.value[k] = BandQuadraticForm(pass.sums[k], pass.coarse.columns, pass.coarse.rows,
                                          pass.coarse.rows, pass.offsets, execution);
      }
      variance[k] += pass.value[k];
      out.block = std::max(out.block, pass.block);
    }
    variance[k] = std::max(0.0, variance[k]);
  }
  out.fill = std::sqrt(variance[0]);
  out.cut = std::sqrt(variance[1]);
  out.net = std::sqrt(variance[2]);
  return out;
}

SpatialSigma PropagateSpatialSigma(const GridLayout& grid, const std::vector<double>& dz,
                                   const std::vector<double>& sigma,
                                   const std::vector<double>& threshold,
                                   const std::vector<double>& area, const Variogram& variogram,
                                   const Execution& execution, double budget) {
  const BudgetRowReader read = [&](int row0, int row1, int, BudgetRows* rows) {
    const auto slice = [&](const std::vector<double>& all, std::vector<double>* part) {
      part->assign(all.begin() + static_cast<std::ptrdiff_t>(row0) * grid.columns,
                   all.begin() + static_cast<std::ptrdiff_t>(row1) * grid.columns);
    };
    slice(dz, &rows->dz), slice(sigma, &rows->sigma), slice(threshold, &rows->threshold),
        slice(area, &rows->area);
  };
  return PropagateSpatialSigma(grid, read, variogram, execution, budget);
}

}  // namespace surfreg

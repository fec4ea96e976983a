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

// The middle value, or the mean of the two middle ones (as the budget's medians).
double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  if (v.size() % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(v.begin(), middle));
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
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
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
  const int count =
      static_cast<int>(std::max<int64_t>(1, std::min<int64_t>(bins, n / kMinBinCells)));
  auto median_key = [&](int64_t begin, int64_t end) {
    std::vector<double> key;
    for (int64_t i = begin; i < end; ++i) key.push_back(samples[static_cast<std::size_t>(i)].first);
    return Median(std::move(key));
  };
  std::vector<std::pair<int64_t, int64_t>> ranges;
  for (int b = 0; b < count; ++b) {
    const int64_t begin = n * b / count, end = n * (b + 1) / count;
    if (!ranges.empty() &&
        !(median_key(begin, end) >
          median_key(ranges.back().first, ranges.back().second) + 1e-9 * scale)) {
      ranges.back().second = end;
    } else {
      ranges.emplace_back(begin, end);
    }
  }
  for (const auto& [begin, end] : ranges) {
    std::vector<double> value;
    for (int64_t i = begin; i < end; ++i)
      value.push_back(samples[static_cast<std::size_t>(i)].second);
    const double s = Nmad(value);
    if (!(s > 0)) continue;
    keys->push_back(median_key(begin, end));
    nmads->push_back(s);
  }
}

}  // namespace

void SlopeAndCurvature(const GridLayout& grid, const std::vector<double>& height,
                       std::vector<double>* slope, std::vector<double>* curvature) {
  const std::size_t n = static_cast<std::size_t>(grid.cells());
  slope->assign(n, std::nan(""));
  curvature->assign(n, std::nan(""));
  const int columns = grid.columns, rows = grid.rows;
  auto at = [&](int x, int y) {
    if (x < 0 || x >= columns || y < 0 || y >= rows) return std::nan("");
    return height[static_cast<std::size_t>(y) * columns + x];
  };
  // Derivative and second derivative along one axis from the two neighbours.
  auto axis = [](double before, double here, double after, double step, double* first,
                 double* second) {
    const bool b = std::isfinite(before), a = std::isfinite(after);
    *second = b && a ? (after - 2 * here + before) / (step * step) : std::nan("");
    *first = b && a ? (after - before) / (2 * step)
             : a    ? (after - here) / step
             : b    ? (here - before) / step
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
        (*curvature)[i] =
            std::fabs((std::isfinite(cx) ? cx : 0.0) + (std::isfinite(cy) ? cy : 0.0));
      }
    }
  }
}

double SigmaModel::At(double s, double c) const {
  return Interpolate(slope, sigma, s) *
         (curvature.empty() ? 1.0 : Interpolate(curvature, factor, c));
}

namespace {

// Rows [row, row + rows) and columns [column, column + columns) of
// `source`, a block `source_columns` wide, into `target` (empty stays empty).
template <typename T>
void CopyRows(const std::vector<T>& source, int source_columns, int column, int row, int columns,
              int rows, std::vector<T>* target) {
  target->clear();
  if (source.empty()) return;
  for (int y = 0; y < rows; ++y) {
    const auto begin =
        source.begin() + static_cast<std::ptrdiff_t>(row + y) * source_columns + column;
    target->insert(target->end(), begin, begin + columns);
  }
}

// The window of `to` (its columns and rows) at (column, row) of `from`, every field.
void CopyWindow(const DodBlock& from, int from_columns, int column, int row, DodBlock* to) {
  const int w = to->columns, h = to->rows;
  CopyRows(from.dz, from_columns, column, row, w, h, &to->dz);
  CopyRows(from.height, from_columns, column, row, w, h, &to->height);
  CopyRows(from.area, from_columns, column, row, w, h, &to->area);
  CopyRows(from.sigma, from_columns, column, row, w, h, &to->sigma);
  CopyRows(from.stable, from_columns, column, row, w, h, &to->stable);
}

}  // namespace

DodBlockReader DodGridReader(const DodGrid& dod) {
  return [&dod](DodBlock* block) {
    CopyWindow(dod.cells, dod.layout.columns, block->column, block->row, block);
  };
}

std::vector<std::array<int, 4>> ErrorModelWindows(const GridLayout& grid) {
  constexpr int64_t kWholeCells = int64_t{1} << 22;
  constexpr int kSide = 1024, kAcross = 4;
  if (grid.cells() <= kWholeCells) return {{0, 0, grid.columns, grid.rows}};
  std::vector<std::array<int, 4>> windows;
  const int columns = std::min(kSide, grid.columns), rows = std::min(kSide, grid.rows);
  for (int j = 0; j < kAcross; ++j) {
    for (int i = 0; i < kAcross; ++i) {
      const int column =
          static_cast<int>(static_cast<int64_t>(grid.columns - columns) * i / (kAcross - 1));
      const int row = static_cast<int>(static_cast<int64_t>(grid.rows - rows) * j / (kAcross - 1));
      const std::array<int, 4> window = {column, row, columns, rows};
      if (std::find(windows.begin(), windows.end(), window) == windows.end())
        windows.push_back(window);
    }
  }
  return windows;
}

namespace {

// The window of `block` with its slope and curvature: read with a cell
// around it (clipped to the grid), then cropped back.
void ReadWithSlope(const GridLayout& grid, const DodBlockReader& read, DodBlock* block,
                   std::vector<double>* slope, std::vector<double>* curvature) {
  DodBlock wide;
  wide.column = std::max(0, block->column - 1), wide.row = std::max(0, block->row - 1);
  wide.columns = std::min(grid.columns, block->column + block->columns + 1) - wide.column;
  wide.rows = std::min(grid.rows, block->row + block->rows + 1) - wide.row;
  read(&wide);
  std::vector<double> wide_slope, wide_curvature;
  SlopeAndCurvature({wide.columns, wide.rows, grid.dx, grid.dy}, wide.height, &wide_slope,
                    &wide_curvature);
  const int dx = block->column - wide.column, dy = block->row - wide.row;
  CopyWindow(wide, wide.columns, dx, dy, block);
  CopyRows(wide_slope, wide.columns, dx, dy, block->columns, block->rows, slope);
  CopyRows(wide_curvature, wide.columns, dx, dy, block->columns, block->rows, curvature);
}

}  // namespace

bool StableInlier(const DodErrorModel& model, bool stable, double dz) {
  return stable && std::isfinite(dz) &&
         std::fabs(dz - model.stable_median) <= kInlierNmads * model.stable_nmad;
}

void ReadWithSigma(const GridLayout& grid, const DodBlockReader& read, const DodErrorModel& model,
                   DodBlock* block, std::vector<double>* sigma) {
  std::vector<double> slope, curvature;
  ReadWithSlope(grid, read, block, &slope, &curvature);
  const std::size_t n = block->dz.size();
  sigma->assign(n, std::nan(""));
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(block->dz[i])) continue;
    (*sigma)[i] = !block->sigma.empty()             ? block->sigma[i]
                  : model.sigma_model.slope.empty() ? 0.0
                                                    : model.sigma_model.At(slope[i], curvature[i]);
  }
}

DodErrorModel FitDodErrorModel(const GridLayout& grid, const DodBlockReader& read,
                               const Execution& execution, const std::string& where) {
  DodErrorModel model;
  struct Window {
    DodBlock block;
    std::vector<double> slope, curvature, standard;
    std::vector<uint8_t> inlier;
  };
  std::vector<Window> windows;
  for (const auto& [column, row, columns, rows] : ErrorModelWindows(grid)) {
    Window w;
    w.block.column = column, w.block.row = row, w.block.columns = columns, w.block.rows = rows;
    ReadWithSlope(grid, read, &w.block, &w.slope, &w.curvature);
    windows.push_back(std::move(w));
  }
  model.sigma_estimated = std::all_of(windows.begin(), windows.end(),
                                      [](const Window& w) { return w.block.sigma.empty(); });
  // The stable cells' dz, and of them the inliers: within 4 NMAD of the
  // median (a change the stable terrain missed is not noise).
  std::vector<double> stable_dz;
  for (const Window& w : windows) {
    for (std::size_t i = 0; i < w.block.dz.size(); ++i) {
      if (w.block.stable[i] && std::isfinite(w.block.dz[i])) stable_dz.push_back(w.block.dz[i]);
    }
  }
  model.stable_median = Median(stable_dz);
  model.stable_nmad = stable_dz.empty() ? std::nan("") : Nmad(stable_dz);
  for (Window& w : windows) {
    w.inlier.assign(w.block.dz.size(), 0);
    for (std::size_t i = 0; i < w.block.dz.size(); ++i) {
      if (StableInlier(model, w.block.stable[i], w.block.dz[i])) {
        w.inlier[i] = 1;
        ++model.stable_cells;
      }
    }
  }
  if (model.stable_cells < kMinStableCells) {
    throw InputError(
        where + ": only " + std::to_string(model.stable_cells) +
        " stable cells with a DoD value, and the variogram error model needs at least " +
        std::to_string(kMinStableCells) + " (a larger stable area, or error_model: independent)");
  }
  if (model.sigma_estimated) {
    std::vector<std::pair<double, double>> by_slope;
    for (const Window& w : windows) {
      for (std::size_t i = 0; i < w.inlier.size(); ++i) {
        if (w.inlier[i] && std::isfinite(w.slope[i]))
          by_slope.emplace_back(w.slope[i], w.block.dz[i]);
      }
    }
    BinnedNmad(std::move(by_slope), kSlopeBins, &model.sigma_model.slope, &model.sigma_model.sigma);
    std::vector<std::pair<double, double>> by_curvature;
    for (const Window& w : windows) {
      for (std::size_t i = 0; i < w.inlier.size(); ++i) {
        if (!w.inlier[i] || !std::isfinite(w.curvature[i])) continue;
        const double s = Interpolate(model.sigma_model.slope, model.sigma_model.sigma, w.slope[i]);
        if (s > 0)
          by_curvature.emplace_back(w.curvature[i], (w.block.dz[i] - model.stable_median) / s);
      }
    }
    BinnedNmad(std::move(by_curvature), kCurvatureBins, &model.sigma_model.curvature,
               &model.sigma_model.factor);
  }
  // σ at every cell; the variogram of the standardized stable dz.
  std::vector<double> sigmas;
  std::vector<GridValues> grids;
  for (Window& w : windows) {
    const std::size_t n = w.block.dz.size();
    w.standard.assign(n, std::nan(""));
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(w.block.dz[i])) continue;
      const double s = !w.block.sigma.empty() ? w.block.sigma[i]
                       : model.sigma_model.slope.empty()
                           ? 0.0
                           : model.sigma_model.At(w.slope[i], w.curvature[i]);
      if (std::isfinite(s) && std::isfinite(w.block.area[i]) && w.block.area[i] > 0)
        sigmas.push_back(s);
      if (w.inlier[i] && s > 0) w.standard[i] = (w.block.dz[i] - model.stable_median) / s;
    }
    grids.push_back({{w.block.columns, w.block.rows, grid.dx, grid.dy}, &w.standard});
  }
  model.sigma_median = Median(std::move(sigmas));
  model.empirical = SampleVariogram(grids, execution);
  const double step = std::min(grid.dx, grid.dy);
  // No range beyond the longest lag seen: there the variogram says nothing.
  const double longest = model.empirical.lag.empty() ? step : model.empirical.lag.back();
  model.variogram = FitVariogram(model.empirical, 0.5 * step, std::max(step, longest));
  return model;
}

}  // namespace surfreg

#include "terrain/change_uncertainty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "measure/input_error.h"
#include "registration/align.h"
#include "io/plot.h"
#include "io/surface_reader_internal.h"
#include "terrain/spatial_budget.h"

namespace surfreg {
namespace {

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string GridText(const Raster& r) {
  const auto& g = r.geotransform;
  char text[160];
  std::snprintf(text, sizeof text, "%d x %d cells of %.10g x %.10g from (%.10g, %.10g)", r.columns,
                r.rows, g[1], std::fabs(g[5]), g[0], g[3]);
  return text;
}

bool SameGrid(const Raster& a, const Raster& b) {
  if (a.columns != b.columns || a.rows != b.rows) return false;
  const double cell = std::max(std::fabs(a.geotransform[1]), std::fabs(a.geotransform[5]));
  for (int k = 0; k < 6; ++k) {
    const bool origin = k == 0 || k == 3;
    const double tolerance = origin ? 1e-6 * cell : 1e-9 * cell;
    if (!(std::fabs(a.geotransform[k] - b.geotransform[k]) <= tolerance)) return false;
  }
  return true;
}

// Whether every value is the same number: the moving σ then needs no interpolation.
bool Constant(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [&](double v) { return v == values.front(); });
}

// The cell sizes in the frame the samples are in (a geographic raster's are
// degrees, its samples metres): the median distance of neighbouring
// samples along a row and along a column.
void FrameCellSize(const Surface& reference, const Raster& grid, const std::vector<int64_t>& cells,
                   const std::vector<int64_t>& sample_of_cell, double* dx, double* dy) {
  std::vector<double> along_row, along_column;
  for (std::size_t i = 0; i < cells.size() && (along_row.size() < 999 || along_column.size() < 999); ++i) {
    const int64_t cell = cells[i];
    const auto distance = [&](int64_t other) {
      const auto& a = reference.xy[i];
      const auto& b = reference.xy[static_cast<std::size_t>(other)];
      return std::hypot(a.x - b.x, a.y - b.y);
    };
    if (cell % grid.columns + 1 < grid.columns && sample_of_cell[cell + 1] >= 0) {
      along_row.push_back(distance(sample_of_cell[cell + 1]));
    }
    if (cell / grid.columns + 1 < grid.rows && sample_of_cell[cell + grid.columns] >= 0) {
      along_column.push_back(distance(sample_of_cell[cell + grid.columns]));
    }
  }
  const auto median = [](std::vector<double> v, double fallback) {
    if (v.empty()) return fallback;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  *dx = median(along_row, std::fabs(grid.geotransform[1]));
  *dy = median(along_column, std::fabs(grid.geotransform[5]));
  if (along_row.empty()) *dx = *dy;
  if (along_column.empty()) *dy = *dx;
}

// error_model variogram: the model on the stable cells (σ_DoD estimated
// when none was given) and the budget's spatially correlated ±.
void AddSpatialUncertainty(const TerrainRequest& config, const Surface& reference, const MeasureSummary& after,
                           const ReferenceCells& at, const Execution& execution, bool sigma_given,
                           ChangeUncertainty* u) {
  const std::string where = config.Where("error_model");
  if (at.grid == nullptr || at.cells == nullptr || at.cells->size() != reference.size()) {
    throw InputError(where + ": the variogram error model needs a raster reference, but " + config.reference +
                     " is a point cloud");
  }
  const Raster& grid = *at.grid;
  const std::vector<int64_t>& cells = *at.cells;
  DodGrid dod;
  dod.layout.columns = grid.columns, dod.layout.rows = grid.rows;
  const std::size_t n = static_cast<std::size_t>(dod.layout.cells());
  std::vector<int64_t> sample_of_cell(n, -1);
  for (std::size_t i = 0; i < cells.size(); ++i) sample_of_cell[static_cast<std::size_t>(cells[i])] = static_cast<int64_t>(i);
  FrameCellSize(reference, grid, cells, sample_of_cell, &dod.layout.dx, &dod.layout.dy);
  DodBlock& all = dod.cells;
  all.columns = grid.columns, all.rows = grid.rows;
  all.dz.assign(n, std::nan(""));
  all.height.assign(n, std::nan(""));
  all.area.assign(n, 0.0);
  all.stable.assign(n, 0);
  if (sigma_given) all.sigma.assign(n, std::nan(""));
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t c = static_cast<std::size_t>(cells[i]);
    all.dz[c] = after.dz_a[i];
    all.height[c] = reference.z[i] + reference.origin[2];
    all.area[c] = u->area[i];
    all.stable[c] = at.stable.empty() || at.stable[i];
    if (sigma_given) all.sigma[c] = u->sigma_dod[i];
  }
  const DodBlockReader read = DodGridReader(dod);
  u->model = FitDodErrorModel(dod.layout, read, execution, where);
  if (!sigma_given) {
    DodBlock whole;
    whole.columns = grid.columns, whole.rows = grid.rows;
    std::vector<double> sigma;
    ReadWithSigma(dod.layout, read, u->model, &whole, &sigma);
    for (std::size_t i = 0; i < cells.size(); ++i) {
      u->sigma_dod[i] = std::isfinite(after.dz_a[i]) ? sigma[static_cast<std::size_t>(cells[i])] : std::nan("");
    }
  }
  const double confidence = config.terrain.lod_confidence;
  const double t = confidence > 0 ? TwoSidedNormalQuantile(confidence) : 0.0;
  const SpatialSigma s = PropagateSpatialSigma(
      dod.layout, DodBudgetRows(dod.layout, read, u->model, t, config.terrain.lod, nullptr), u->model.variogram,
      execution);
  u->spatial = true;
  u->fill_sigma_spatial = s.fill, u->cut_sigma_spatial = s.cut, u->net_sigma_spatial = s.net;
  u->spatial_block = s.block;
}

}  // namespace

BudgetRowReader DodBudgetRows(const GridLayout& grid, const DodBlockReader& read, const DodErrorModel& model,
                              double t, double lod, ChangeBudgetSums* sums) {
  return [&grid, read, &model, t, lod, sums](int row0, int row1, int core, BudgetRows* rows) {
    DodBlock block;
    block.column = 0, block.row = row0, block.columns = grid.columns, block.rows = row1 - row0;
    ReadWithSigma(grid, read, model, &block, &rows->sigma);
    rows->noise.resize(block.dz.size());
    for (std::size_t i = 0; i < block.dz.size(); ++i) rows->noise[i] = StableInlier(model, block.stable[i], block.dz[i]);
    rows->dz = std::move(block.dz);
    rows->area = std::move(block.area);
    rows->threshold.resize(rows->sigma.size());
    for (std::size_t i = 0; i < rows->sigma.size(); ++i) {
      rows->threshold[i] = std::isfinite(rows->sigma[i]) ? std::max(lod, t * rows->sigma[i]) : std::nan("");
    }
    if (sums == nullptr) return;
    const std::size_t first = static_cast<std::size_t>(core) * static_cast<std::size_t>(grid.columns);
    for (std::size_t i = 0; i < first; ++i) sums->AddNode(rows->dz[i], rows->area[i], rows->sigma[i], rows->threshold[i]);
  };
}

ChangeSigmas ModelSigmas(const ChangeUncertainty& u) {
  const ChangeBudget& b = u.budget;
  if (u.spatial) return {u.fill_sigma_spatial, u.cut_sigma_spatial, u.net_sigma_spatial};
  if (u.error_model == "correlated") {
    return {b.fill_sigma_correlated, b.cut_sigma_correlated, b.net_sigma_correlated};
  }
  return {b.fill_sigma_independent, b.cut_sigma_independent, b.net_sigma_independent};
}

std::vector<double> SigmaPerSample(const TerrainRequest& config, const std::string& key,
                                   std::size_t samples, const Raster& grid,
                                   const std::vector<int64_t>& cells) {
  const std::string sigma_key = "sigma_" + key;
  const std::string& text = key == "reference" ? config.terrain.sigma_reference : config.terrain.sigma_moving;
  if (text.empty()) return {};
  const std::string where = config.Where(sigma_key);
  double value = 0;
  if (io_internal::ParseNumber(text, &value) == io_internal::NumberStatus::kOk) {
    return std::vector<double>(samples, value);  // >= 0: checked by the key
  }
  const std::string& dem = InputPath(config, key);
  if (cells.size() != samples) {
    throw InputError(where + ": a σ raster needs a raster DEM, but " + dem +
                     " is a point cloud (give one number)");
  }
  Raster sigma;
  try {
    RasterReadOptions options;  // band 1, the DEM's window: the same cells
    const auto& w = config.terrain.window;
    options.window = {w[0], w[1], w[2], w[3]};
    sigma = ReadRaster(text, options);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  if (!SameGrid(sigma, grid)) {
    throw InputError(where + ": the σ raster " + text + " (" + GridText(sigma) +
                     ") is not on the grid of " + dem + " (" + GridText(grid) + ")");
  }
  std::vector<double> out(samples);
  int64_t missing = 0;
  for (std::size_t i = 0; i < samples; ++i) {
    out[i] = sigma.values[static_cast<std::size_t>(cells[i])];
    if (!std::isfinite(out[i])) {
      ++missing;
    } else if (out[i] < 0) {
      const int64_t column = cells[i] % sigma.columns, row = cells[i] / sigma.columns;
      throw InputError(where + ": " + text + " has a negative σ (" + Number(out[i]) + ") at cell (" +
                       std::to_string(column) + ", " + std::to_string(row) + ")");
    }
  }
  if (missing > 0) {
    throw InputError(where + ": " + text + " has no value at " + std::to_string(missing) + " of the " +
                     std::to_string(samples) + " valid cells of " + dem);
  }
  return out;
}

ChangeUncertainty AnalyseChangeUncertainty(const TerrainRequest& config, const Surface& reference,
                                           const Surface& moved, const std::vector<double>& sigma_reference,
                                           const std::vector<double>& sigma_moving,
                                           const MeasureSummary& after, const MeasureOptions& options,
                                           const ReferenceCells& cells) {
  ChangeUncertainty u;
  u.error_model = config.terrain.error_model;
  const bool variogram = u.error_model == "variogram";
  const bool sigma_given = !sigma_reference.empty() || !sigma_moving.empty();
  if (!sigma_given && !variogram) return u;
  u.active = true;
  const std::size_t n = reference.size();
  const std::vector<double> sa = sigma_reference.empty() ? std::vector<double>(n, 0.0) : sigma_reference;
  std::vector<double> sb(n, 0.0);
  if (!sigma_moving.empty() && Constant(sigma_moving)) {
    sb.assign(n, sigma_moving.front());
  } else if (!sigma_moving.empty()) {
    // The moving σ as a surface on the moved mesh, measured against a flat
    // reference on its own: the "gap" at each reference node is σ_B there.
    Surface flat = reference;
    flat.origin[2] = 0;
    std::fill(flat.z.begin(), flat.z.end(), 0.0);
    Surface field = moved;
    field.origin[2] = 0;
    field.z = sigma_moving;
    MeasureOptions at_nodes = options;
    at_nodes.detect_change = false;
    at_nodes.weight = WeightMode::kUniform;
    sb = Measure(flat, field, at_nodes).dz_a;
  }
  u.sigma_dod = PropagateSigma(sa, sb);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(after.dz_a[i])) u.sigma_dod[i] = std::nan("");
  }
  u.area = after.node_area_a;
  u.area.resize(n, 0.0);
  if (!cells.counted.empty()) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!cells.counted[i]) u.area[i] = 0;
    }
  }
  if (variogram) {
    AddSpatialUncertainty(config, reference, after, cells, ExecutionFor(options.threads), sigma_given, &u);
  }
  const double confidence = config.terrain.lod_confidence, lod = config.terrain.lod;
  u.threshold = ChangeThresholds(u.sigma_dod, confidence, lod);
  std::vector<double> sigma_counted = u.sigma_dod;  // the medians over the counted nodes
  if (!cells.counted.empty()) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!cells.counted[i]) sigma_counted[i] = std::nan("");
    }
  }
  u.budget = ComputeChangeBudget(after.dz_a, u.area, sigma_counted, confidence, lod);
  return u;
}

void AddRegistrationUncertainty(const Surface& reference, const Surface& moving,
                                const std::array<double, 3>& rotation_vector,
                                const std::array<double, 3>& translation, const std::array<double, 3>& centre,
                                const Eigen::Matrix<double, 6, 6>& covariance, const MeasureSummary& after,
                                const MeasureOptions& options, ChangeUncertainty* u) {
  if (!u->active) return;
  const std::size_t n = reference.size();
  // Which nodes the budget counted, as gain or loss.
  std::vector<int8_t> side(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double dz = after.dz_a[i];
    if (!std::isfinite(dz) || !std::isfinite(u->sigma_dod[i])) continue;
    side[i] = dz > u->threshold[i] ? 1 : dz < -u->threshold[i] ? -1 : 0;
  }
  const Eigen::Vector3d c(centre[0], centre[1], centre[2]);
  auto matrix_of = [&](const Eigen::Matrix<double, 6, 1>& theta) {
    const Eigen::Vector3d w = theta.head<3>();
    const double angle = w.norm();
    const Eigen::Matrix3d r =
        angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = r;
    m.topRightCorner<3, 1>() = c + theta.tail<3>() - r * c;
    return m;
  };
  Eigen::Matrix<double, 6, 1> theta;
  theta << rotation_vector[0], rotation_vector[1], rotation_vector[2], translation[0], translation[1], translation[2];
  MeasureOptions at_nodes = options;
  at_nodes.keep_node_gaps = true;
  at_nodes.detect_change = false;
  Eigen::Matrix<double, 6, 1> fill = Eigen::Matrix<double, 6, 1>::Zero(), cut = fill;
  for (int k = 0; k < 6; ++k) {
    const double variance = covariance(k, k);
    if (!(std::isfinite(variance) && variance > 0)) continue;
    const double h = std::sqrt(variance);
    Eigen::Matrix<double, 6, 1> step = Eigen::Matrix<double, 6, 1>::Zero();
    step[k] = h;
    const std::vector<double> up = Measure(reference, TransformSurface(moving, matrix_of(theta + step)), at_nodes).dz_a;
    const std::vector<double> down = Measure(reference, TransformSurface(moving, matrix_of(theta - step)), at_nodes).dz_a;
    for (std::size_t i = 0; i < n; ++i) {
      if (side[i] == 0 || !std::isfinite(up[i]) || !std::isfinite(down[i])) continue;
      const double derivative = (up[i] - down[i]) / (2 * h) * u->area[i];
      (side[i] > 0 ? fill : cut)[k] += side[i] > 0 ? derivative : -derivative;  // cut counts |dz|
    }
  }
  Eigen::Matrix<double, 6, 6> cov = covariance;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      if (!std::isfinite(cov(i, j))) cov(i, j) = 0;
    }
  }
  const Eigen::Matrix<double, 6, 1> net = fill - cut;
  u->registration = true;
  u->fill_sigma_registration = std::sqrt(std::max(0.0, fill.dot(cov * fill)));
  u->cut_sigma_registration = std::sqrt(std::max(0.0, cut.dot(cov * cut)));
  u->net_sigma_registration = std::sqrt(std::max(0.0, net.dot(cov * net)));
  const ChangeSigmas dem = ModelSigmas(*u);
  u->fill_sigma_total = std::hypot(dem.fill, u->fill_sigma_registration);
  u->cut_sigma_total = std::hypot(dem.cut, u->cut_sigma_registration);
  u->net_sigma_total = std::hypot(dem.net, u->net_sigma_registration);
}

void WriteVariogramPng(const std::string& path, const DodErrorModel& model, const std::string& units,
                       const std::string& where) {
  const EmpiricalVariogram& e = model.empirical;
  const Variogram& v = model.variogram;
  std::vector<Series> series(2);
  series[0].name = "empirical (stable terrain)";
  series[0].x = e.lag, series[0].y = e.gamma;
  series[0].line = false, series[0].markers = true;
  series[1].name = "fit: nugget " + Number(v.nugget) + ", sills " + Number(v.sill[0]) + " / " +
                   Number(v.sill[1]) + ", ranges " + Number(v.range[0]) + " / " + Number(v.range[1]);
  const double first = e.lag.empty() ? 1.0 : e.lag.front(), last = e.lag.empty() ? 1.0 : e.lag.back();
  for (int k = 0; k <= 200; ++k) {
    const double h = first * std::pow(last / first, k / 200.0);
    series[1].x.push_back(h);
    series[1].y.push_back(v.Gamma(h));
  }
  const FigureText text{"variogram of dz / sigma on stable terrain", "lag (" + units + ")",
                        "semivariance (dz / sigma)^2"};
  ChartStyle style;
  style.log_x = true;
  WriteChartPng(path, series, text, style, where);
}

std::string ChangeUncertaintySummary(const TerrainRequest& config, const ChangeUncertainty& u,
                                     const std::string& units) {
  const ChangeBudget& b = u.budget;
  const TerrainSettings& t = config.terrain;
  std::string text = "uncertainty:  sigma_DoD median " + Number(b.sigma_median) + " " + units +
                     " (reference " + (t.sigma_reference.empty() ? "0" : t.sigma_reference) +
                     ", moving " + (t.sigma_moving.empty() ? "0" : t.sigma_moving) + ")";
  text += "; change where |dz| > ";
  if (t.lod_confidence > 0) {
    text += Number(b.t) + " sigma_DoD (" + Number(100 * t.lod_confidence) + "%)";
    if (t.lod > 0) text += " and > lod " + Number(t.lod);
  } else {
    text += "lod " + Number(t.lod);
  }
  text += " (median threshold " + Number(b.threshold_median) + ")\n";
  const std::string cube = units == "m" ? "m^3" : "units^3";
  auto line = [&](const char* name, double value, double independent, double correlated) {
    return std::string(name) + " " + Number(value) + " +/- " + Number(independent) + " (independent) / " +
           Number(correlated) + " (correlated)";
  };
  text += "change +/-:   " + line("fill", b.fill, b.fill_sigma_independent, b.fill_sigma_correlated) + ", " +
          line("cut", b.cut, b.cut_sigma_independent, b.cut_sigma_correlated) + ",\n              " +
          line("net", b.net, b.net_sigma_independent, b.net_sigma_correlated) + " " + cube + "\n";
  text += "              cellwise over " + std::to_string(b.fill_nodes) + " + " + std::to_string(b.cut_nodes) +
          " of " + std::to_string(b.nodes) + " nodes" + (t.change_mask.empty() ? "" : " inside " + t.change_mask) + "; areas of detected gain " + Number(b.fill_area) +
          " and loss " + Number(b.cut_area) + " " + (units == "m" ? "m^2" : "units^2");
  if (u.spatial) {
    const Variogram& v = u.model.variogram;
    text += "\n              spatially correlated (variogram): fill +/- " + Number(u.fill_sigma_spatial) + ", cut +/- " +
            Number(u.cut_sigma_spatial) + ", net +/- " + Number(u.net_sigma_spatial) + " " + cube;
    if (u.spatial_block > 1) text += " (blocks of " + std::to_string(u.spatial_block) + " cells)";
    text += "\n              variogram of dz/sigma on " + std::to_string(u.model.stable_cells) +
            " stable cells: nugget " + Number(v.nugget) + ", sill " + Number(v.sill[0]) + " range " +
            Number(v.range[0]) + ", sill " + Number(v.sill[1]) + " range " + Number(v.range[1]) + " " + units;
    if (u.model.sigma_estimated && !u.model.sigma_model.sigma.empty()) {
      const auto& m = u.model.sigma_model;
      text += "; sigma_DoD " + Number(m.sigma.front()) + " to " + Number(m.sigma.back()) + " " + units +
              " from slope " + Number(m.slope.front()) + " to " + Number(m.slope.back());
    }
  }
  if (u.registration) {
    text += "\n              registration +/- fill " + Number(u.fill_sigma_registration) + ", cut " +
            Number(u.cut_sigma_registration) + ", net " + Number(u.net_sigma_registration) +
            " (from the motion's covariance); with the " + u.error_model + " DEM errors: fill +/- " + Number(u.fill_sigma_total) +
            ", cut +/- " + Number(u.cut_sigma_total) + ", net +/- " + Number(u.net_sigma_total);
  }
  return text;
}

}  // namespace surfreg

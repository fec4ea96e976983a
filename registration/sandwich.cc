#include "registration/sandwich.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Eigenvalues>

#include "measure/overlay.h"
#include "registration/axial_cost.h"
#include "registration/volume_cost/volume_accumulator.h"
#include "registration/volume_cost/volume_cost.h"
#include "registration/volume_cost/volume_hessian.h"

namespace surfreg {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// Fine tiles over A's bounding box, merged k × k into the tiles used: fine
// enough that some k gives about kSandwichTiles non-empty tiles on any
// overlap shape, coarse enough to stay cheap.
constexpr int kFineTiles = 64;

struct TileSums {
  double abs = 0, area = 0;
  Vector6 d_abs = Vector6::Zero(), d_area = Vector6::Zero();
  bool used = false;
};

// The fine tiles: squares over the bounding box of A's nodes.
struct FineGrid {
  double x0 = 0, y0 = 0, side = 1;
  int Index(double x, double y) const {
    const int i = std::clamp(static_cast<int>((x - x0) / side), 0, kFineTiles - 1);
    const int j = std::clamp(static_cast<int>((y - y0) / side), 0, kFineTiles - 1);
    return j * kFineTiles + i;
  }
};

FineGrid FineGridOf(const std::vector<Point2>& xy) {
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
  for (const Point2& p : xy) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  FineGrid grid;
  grid.x0 = lo_x, grid.y0 = lo_y;
  grid.side = std::max(hi_x - lo_x, hi_y - lo_y) / kFineTiles;
  if (!(grid.side > 0)) grid.side = 1;
  return grid;
}

// The same fine tiles as the volume cost's gradient bins.
GradientBins BinsOver(const std::vector<Point2>& xy) {
  const FineGrid grid = FineGridOf(xy);
  GradientBins bins;
  bins.x0 = grid.x0, bins.y0 = grid.y0, bins.side = grid.side, bins.n = kFineTiles;
  return bins;
}

// Bins the cells an accumulator takes into fine tiles by their centroid.
struct alignas(64) TileBinner {  // a cache line of its own (one per chunk)
  TileBinner(const PairState& state, const MaskRegion* mask, const FineGrid& fine_grid)
      : accumulator(state, /*gradient=*/true, mask), grid(fine_grid), tiles(kFineTiles * kFineTiles) {}
  void operator()(const OverlayCell& cell) {
    const VolumeCostValue before = accumulator.value;
    accumulator(cell);
    const VolumeCostValue& after = accumulator.value;
    if (after.cells == before.cells) return;  // not on both surfaces
    double cx = 0, cy = 0;
    for (int k = 0; k < cell.num_vertices; ++k) cx += cell.vertices[k].x, cy += cell.vertices[k].y;
    TileSums& t = tiles[grid.Index(cx / cell.num_vertices, cy / cell.num_vertices)];
    t.abs += after.abs - before.abs;
    t.area += after.area - before.area;
    t.d_abs += after.d_abs - before.d_abs;
    t.d_area += after.d_area - before.d_area;
    t.used = true;
  }
  volume_internal::VolumeAccumulator accumulator;
  FineGrid grid;
  std::vector<TileSums> tiles;
};

// Per fine tile, the parts of ∫μ|d|, ∫μ and their gradients from the cells
// whose centroid lies in it (the integrals of EvaluateVolumeCost, split),
// in chunks (at most 8: each holds all the tiles) on the threads allowed.
std::vector<TileSums> FineTileSums(const PairState& state, const MaskRegion* mask,
                                   const Execution& execution) {
  const FineGrid grid = FineGridOf(state.reference().xy);
  std::vector<TileBinner> parts(std::min(volume_internal::StateChunks(state), 8), TileBinner(state, mask, grid));
  volume_internal::ForEachCellOfState(state, execution, parts);
  TileBinner& first = parts[0];
  for (std::size_t c = 1; c < parts.size(); ++c) {
    for (std::size_t t = 0; t < first.tiles.size(); ++t) {
      const TileSums& o = parts[c].tiles[t];
      if (!o.used) continue;
      TileSums& m = first.tiles[t];
      m.abs += o.abs, m.area += o.area, m.d_abs += o.d_abs, m.d_area += o.d_area;
      m.used = true;
    }
  }
  return std::move(first.tiles);
}

// The fine tiles merged k × k, for the k that gives closest to `target`
// non-empty tiles (in ratio).
std::vector<TileSums> MergedTiles(const std::vector<TileSums>& fine, int target) {
  std::vector<TileSums> best;
  double best_misfit = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= kFineTiles; ++k) {
    const int n = (kFineTiles + k - 1) / k;
    std::vector<TileSums> merged(n * n);
    for (int j = 0; j < kFineTiles; ++j) {
      for (int i = 0; i < kFineTiles; ++i) {
        const TileSums& f = fine[j * kFineTiles + i];
        if (!f.used) continue;
        TileSums& m = merged[(j / k) * n + i / k];
        m.abs += f.abs, m.area += f.area, m.d_abs += f.d_abs, m.d_area += f.d_area;
        m.used = true;
      }
    }
    merged.erase(std::remove_if(merged.begin(), merged.end(), [](const TileSums& t) { return !t.used; }),
                 merged.end());
    const double misfit = std::fabs(std::log(std::max<double>(1, merged.size()) / target));
    if (misfit < best_misfit) best_misfit = misfit, best = std::move(merged);
  }
  return best;
}

int TileTarget(const PairState& state) {
  return SandwichTileCount(std::min(state.reference().xy.size(), state.moved_xy().size()));
}

// The spread of the tiles' scores: Σ_b (s_b − s̄)(s_b − s̄)ᵀ · B / (B − p),
// p the free parameters the fit took from them.
Matrix6 ScoreSpread(const std::vector<Vector6>& scores, int free_parameters) {
  Vector6 mean = Vector6::Zero();
  for (const Vector6& score : scores) mean += score;
  mean /= static_cast<double>(scores.size());
  Matrix6 spread = Matrix6::Zero();
  for (const Vector6& score : scores) spread += (score - mean) * (score - mean).transpose();
  const double b = static_cast<double>(scores.size());
  return spread * (b / (b - std::max(1, free_parameters)));
}

// H⁻¹ M H⁻¹ on the free parameters, in units where rotation and translation
// weigh alike (the positive-definiteness check and the inverse are then
// well conditioned); locked rows and columns 0. Not ok unless H is
// positive definite.
bool Sandwich(const Matrix6& hessian, const Matrix6& meat, const std::vector<int>& free, double rotation_scale,
              Matrix6* covariance) {
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd h(n, n), m(n, n);
  Eigen::VectorXd scale(n);
  for (int i = 0; i < n; ++i) scale[i] = free[i] < 3 ? rotation_scale : 1.0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      h(i, j) = 0.5 * (hessian(free[i], free[j]) + hessian(free[j], free[i])) / (scale[i] * scale[j]);
      m(i, j) = meat(free[i], free[j]) / (scale[i] * scale[j]);
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(h);
  const Eigen::VectorXd lambda = eigen.eigenvalues();
  if (!(lambda.minCoeff() > 1e-12 * lambda.maxCoeff())) return false;
  const Eigen::MatrixXd inverse = eigen.eigenvectors() * lambda.cwiseInverse().asDiagonal() *
                                  eigen.eigenvectors().transpose();
  const Eigen::MatrixXd c = inverse * m * inverse;
  covariance->setZero();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) (*covariance)(free[i], free[j]) = c(i, j) / (scale[i] * scale[j]);
  }
  return covariance->allFinite();
}

std::vector<int> FreeParameters(const AlignOptions& options) {
  std::vector<int> free;
  for (int k = 0; k < 6; ++k) {
    if (options.free[k]) free.push_back(k);
  }
  return free;
}

}  // namespace

int SandwichTileCount(std::size_t smaller_cloud_nodes) {
  const std::size_t count = smaller_cloud_nodes / kSandwichNodesPerTile;
  return static_cast<int>(std::clamp<std::size_t>(count, kSandwichTiles, kMaxSandwichTiles));
}

SandwichEstimate SandwichCovariance(const PairState& state, const SolveContext& context,
                                    VolumeCostCache* given_cache) {
  SandwichEstimate out;
  const AlignOptions& options = *context.options;
  const MaskRegion* mask =
      context.axial.mask.get();
  const std::vector<int> free = FreeParameters(options);
  const int n = static_cast<int>(free.size());
  if (n == 0) return out;

  // The meat: the spread of the tiles' shares of ∇f. Unmasked, from the
  // evaluation at θ that starts the bread's cache (each moved B triangle's
  // share, by its centroid); masked, from a pass over the cells.
  const Execution execution = ExecutionFor(options.num_threads);
  std::optional<VolumeCostCache> own_cache;
  if (given_cache == nullptr) own_cache.emplace(0.25, options.cell_kernel);
  VolumeCostCache& cache = given_cache != nullptr ? *given_cache : *own_cache;
  std::vector<TileSums> fine;
  double abs = 0, area = 0;
  if (mask == nullptr) {
    GradientBins bins = BinsOver(state.reference().xy);
    const VolumeCostValue value = cache.Evaluate(state, true, execution, nullptr, &bins);
    abs = value.abs, area = value.area;
    fine.resize(bins.used.size());
    for (std::size_t b = 0; b < fine.size(); ++b) {
      fine[b].d_abs = bins.d_abs[b], fine[b].d_area = bins.d_area[b], fine[b].used = bins.used[b] != 0;
    }
  } else {
    fine = FineTileSums(state, mask, execution);
    for (const TileSums& t : fine) abs += t.abs, area += t.area;
  }
  const std::vector<TileSums> tiles = MergedTiles(fine, TileTarget(state));
  out.tiles = static_cast<int>(tiles.size());
  if (out.tiles < 2 * n) return out;
  if (!(area > 0)) return out;
  const double f = abs / area;
  std::vector<Vector6> scores;
  for (const TileSums& t : tiles) scores.push_back((t.d_abs - f * t.d_area) / area);
  const Matrix6 meat = ScoreSpread(scores, n);

  // The bread: the cost's curvature from its zero set and B's kinks
  // (registration/volume_cost/volume_hessian.h), one pass over the cells at θ.
  const Matrix6 hessian =
      (mask == nullptr ? cache.InteriorHessian(state, execution) : InteriorVolumeHessian(state, execution, mask)) /
      area;
  out.ok = Sandwich(hessian, meat, free, context.rotation_scale, &out.covariance);
  return out;
}

namespace {

// Jᵀr of the axial residuals at the state's θ.
Vector6 AxialGradient(const PairState& state, const AxialSettings& settings) {
  AxialResiduals residuals;
  ComputeAxialResiduals(state, settings, /*jacobians=*/true, &residuals);
  Vector6 g = Vector6::Zero();
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (residuals.active[k]) g += residuals.r[k] * Eigen::Map<const Vector6>(residuals.jacobian[k].data());
  }
  return g;
}

}  // namespace

Matrix6 AxialScoreSpread(const PairState& state, const AxialResiduals& residuals, int free_parameters,
                         int* tiles) {
  // Nodes: A's first, then B's (moved); binned by where they lie, over the
  // same fine grid on A's bounding box as the volume cost's cells.
  const ReferenceSide& a = state.reference();
  const FineGrid grid = FineGridOf(a.xy);
  std::vector<TileSums> fine(kFineTiles * kFineTiles);
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (!residuals.active[k]) continue;
    const Point2& p = k < a.xy.size() ? a.xy[k] : state.moved_xy()[k - a.xy.size()];
    TileSums& t = fine[grid.Index(p.x, p.y)];
    t.d_abs += residuals.r[k] * Eigen::Map<const Vector6>(residuals.jacobian[k].data());  // its share of Jᵀr
    t.used = true;
  }
  const std::vector<TileSums> merged = MergedTiles(fine, TileTarget(state));
  *tiles = static_cast<int>(merged.size());
  if (merged.size() <= static_cast<std::size_t>(std::max(1, free_parameters))) return Matrix6::Zero();
  std::vector<Vector6> scores;
  for (const TileSums& t : merged) scores.push_back(t.d_abs);
  return ScoreSpread(scores, free_parameters);
}

SandwichEstimate AxialSandwichCovariance(PairState& state, const SolveContext& context,
                                         const std::array<double, 6>& step) {
  SandwichEstimate out;
  const std::vector<int> free = FreeParameters(*context.options);
  const int n = static_cast<int>(free.size());
  if (n == 0) return out;
  const std::array<double, 6> theta = state.theta();
  AxialResiduals residuals;
  ComputeAxialResiduals(state, context.axial, /*jacobians=*/true, &residuals);
  const Matrix6 meat = AxialScoreSpread(state, residuals, n, &out.tiles);
  if (out.tiles < 2 * n) return out;
  // The bread by central differences of Jᵀr, not JᵀJ: on noisy surfaces the
  // Jacobian's slopes carry the noise too, and JᵀJ then overstates the
  // curvature along the horizontal motions (the Gauss-Newton bread gave
  // error / σ 2.1 for rz, 1.5 for tx and ty in tests/stddev_calibration_test.cc).
  Matrix6 hessian = Matrix6::Zero();
  for (int k : free) {
    bool done = false;
    for (double h = step[k]; !done && h > 0 && std::isfinite(h) && h > 1e-6 * step[k]; h *= 0.25) {
      std::array<double, 6> plus = theta, minus = theta;
      plus[k] += h, minus[k] -= h;
      if (!state.Update(plus)) continue;
      const Vector6 g_plus = AxialGradient(state, context.axial);
      if (!state.Update(minus)) continue;
      hessian.col(k) = (g_plus - AxialGradient(state, context.axial)) / (2 * h);
      done = true;
    }
    if (!done) {
      state.Update(theta);
      return out;
    }
  }
  state.Update(theta);
  out.ok = Sandwich(hessian, meat, free, context.rotation_scale, &out.covariance);
  return out;
}

}  // namespace surfreg

#include "terrain/tiled_measure.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>
#include <utility>

#include "io/raster_io.h"
#include "measure/grid_cells.h"
#include "measure/input_error.h"
#include "measure/mask_region.h"
#include "measure/predicates.h"
#include "terrain/tiled_partial.h"
#include "terrain/tiled_windows.h"
#include "measure/weights.h"

namespace surfreg {
namespace {

// The convex hull of a tile's samples. On an affine grid (to rounding) each
// row's samples lie on one line, so the row's two ends stand for it: no
// orientation test on a whole row of collinear points (each would need the
// exact stage). A moved raster's: the samples on its rim when it is near
// a lattice (grid_cells::HullCandidates); otherwise all samples.
std::vector<Point2> TileHull(const Surface& s, const Execution& execution) {
  grid_cells::GridAffine fit;
  double tolerance = 0.0;
  if (!s.raster_grid()) return ConvexHull(s.xy);
  if (!grid_cells::FitAffine(s, grid_cells::Magnitude(s), &fit, &tolerance)) {
    grid_cells::GridIndex index;  // a moved raster: its rim (HullCandidates)
    if (!grid_cells::BuildIndex(s.raster_cell, &index)) return ConvexHull(s.xy);
    return ConvexHull(grid_cells::HullCandidates(s, index, execution));
  }
  std::vector<Point2> ends;
  for (std::size_t i = 0; i < s.size();) {  // runs of one row (the reader's row-major order)
    std::size_t first = i, last = i, j = i;
    for (; j < s.size() && s.raster_cell[j].row == s.raster_cell[i].row; ++j) {
      if (s.raster_cell[j].column < s.raster_cell[first].column) first = j;
      if (s.raster_cell[j].column > s.raster_cell[last].column) last = j;
    }
    ends.push_back(s.xy[first]);
    if (last != first) ends.push_back(s.xy[last]);
    i = j;
  }
  return ConvexHull(std::move(ends));
}

using tiled_internal::CompleteCellArea;
using tiled_internal::MergeHull;
using tiled_internal::TileBorder;
using tiled_internal::WindowIndex;

using Clock = std::chrono::steady_clock;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// A reference node on a tile border: the parts the tiles holding it saw.
struct BorderNode {
  double dz = kNaN;   // finite if some tile has it in Ω
  double area = 0.0;  // sum of the tiles' parts
};

// A moving node exactly on a tile border, counted by the first tile.
struct SharedNode {
  double dz = 0, weight = 0;
  int64_t tile_row = 0;  // of that tile: only rows up to one below can see it again
};

// Counts the listed moving nodes first seen in tile rows < `before` (no
// later tile can list them again), in key order for deterministic sums;
// but those of tile row `keep` (a band's first, whose top edge another part
// measures): the merge counts them.
void FlushShared(std::unordered_map<int64_t, SharedNode>* shared, int64_t before, int64_t keep,
                 TiledSums* totals) {
  std::vector<std::pair<int64_t, SharedNode>> done;
  for (auto it = shared->begin(); it != shared->end();) {
    if (it->second.tile_row < before && it->second.tile_row != keep) {
      done.emplace_back(*it);
      it = shared->erase(it);
    } else {
      ++it;
    }
  }
  std::sort(done.begin(), done.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
  for (const auto& entry : done) totals->AddNode(entry.second.dz, entry.second.weight);
}

void CheckOptions(const TiledRasterSource& reference, const TiledRasterSource& moving,
                  const TiledMeasureOptions& options) {
  std::string error;
  if (!options.measure.IsValid(&error)) throw InputError("measure options: " + error);
  if (options.tile < 1) {
    throw InputError("tile must be at least 1 cell (got " + std::to_string(options.tile) + ")");
  }
  if (options.margin < 1) throw InputError("tile margin must be at least 1 sample");
  if (options.measure.weight == WeightMode::kPerPoint) {
    throw InputError("tiled measure: per-point weights are not supported yet");
  }
  if (options.measure.volume != VolumeMode::kOverlay) {
    throw InputError("tiled measure: the union volume mode is not local; use the overlay mode");
  }
  if (options.measure.domain.kind != DomainKind::kData) {
    throw InputError("tiled measure: the hull domain is not local; use the data domain");
  }
  if (!reference.read || !moving.read || !moving.cover) {
    throw InputError("tiled measure: a raster source lacks its read (or the moving one its cover)");
  }
  if (reference.columns < 0 || reference.rows < 0 || moving.columns < 0 || moving.rows < 0) {
    throw InputError("tiled measure: negative raster size");
  }
}

Surface ReadChecked(const TiledRasterSource& source, const SampleWindow& window) {
  Surface s = source.read(window);
  if (s.origin != source.origin) {
    throw InputError(WindowIndex::Name(s) + ": a window was read with another origin than the "
                     "source's (the tiles would not add up exactly)");
  }
  if (s.raster_cell.size() != s.xy.size() || s.z.size() != s.xy.size()) {
    throw InputError(WindowIndex::Name(s) + ": a window read without one raster cell per sample");
  }
  return s;
}

int64_t Tiles(int32_t samples, int32_t tile) {
  const int64_t cells = std::max<int64_t>(samples - 1, 0);
  return (cells + tile - 1) / tile;
}

// The samples tile t of a grid of side `tile` reads (its cells and the far
// corner row and column) and owns (half-open, the last tiles to the edge).
void TileWindows(int32_t columns, int32_t rows, int32_t tile, int64_t tx, int64_t ty,
                 SampleWindow* read, SampleWindow* owned) {
  const int64_t c0 = tx * tile, r0 = ty * tile;
  const int64_t c1 = std::min<int64_t>(c0 + tile, columns - 1);
  const int64_t r1 = std::min<int64_t>(r0 + tile, rows - 1);
  *read = {static_cast<int32_t>(c0), static_cast<int32_t>(r0), static_cast<int32_t>(c1 - c0 + 1),
           static_cast<int32_t>(r1 - r0 + 1)};
  *owned = *read;
  if (c1 < columns - 1) --owned->columns;
  if (r1 < rows - 1) --owned->rows;
}

// Domain area, hull and sample count of the moving raster, from its own
// blocks of cells (its windows in the reference's tiles overlap).
void MovingPass(const TiledRasterSource& moving, const TiledMeasureOptions& options,
                int64_t first_row, int64_t end_row, TiledSums* totals, TiledProgress* progress) {
  const int64_t nx = Tiles(moving.columns, options.tile);
  for (int64_t ty = first_row; ty < end_row; ++ty) {
    for (int64_t tx = 0; tx < nx; ++tx) {
      SampleWindow read, owned;
      TileWindows(moving.columns, moving.rows, options.tile, tx, ty, &read, &owned);
      const Surface b = ReadChecked(moving, read);
      const WindowIndex index(b, read);
      int64_t cells = 0;
      totals->domain_area_b += CompleteCellArea(b, index, read.column, read.column + read.columns - 1,
                                                read.row, read.row + read.rows - 1, &cells);
      totals->complete_cells_b += cells;
      for (const RasterCell& cell : b.raster_cell) {
        if (cell.column < owned.column + owned.columns && cell.row < owned.row + owned.rows) {
          ++totals->sum.n_points_b;
        }
      }
      MergeHull(TileHull(b, ExecutionFor(options.measure.threads)), &totals->hull_b);
      ++progress->done;
      if (options.on_progress) options.on_progress(*progress);
    }
  }
}

SampleWindow ClipWindow(SampleWindow w, int32_t margin, int32_t columns, int32_t rows) {
  if (w.empty()) return {};
  const int64_t c0 = std::max<int64_t>(int64_t{w.column} - margin, 0);
  const int64_t r0 = std::max<int64_t>(int64_t{w.row} - margin, 0);
  const int64_t c1 = std::min<int64_t>(int64_t{w.column} + w.columns + margin, columns);
  const int64_t r1 = std::min<int64_t>(int64_t{w.row} + w.rows + margin, rows);
  if (c1 <= c0 || r1 <= r0) return {};
  return {static_cast<int32_t>(c0), static_cast<int32_t>(r0), static_cast<int32_t>(c1 - c0),
          static_cast<int32_t>(r1 - r0)};
}

}  // namespace

namespace {

int64_t NodeKey(int32_t c, int32_t r, int32_t columns) { return static_cast<int64_t>(r) * columns + c; }

// One part's run over its band of tiles: what every tile reads, and the
// state that crosses tiles (reference nodes on tile borders, moving nodes
// exactly on tile borders, the band's first sample row for the merge).
struct PartRun {
  PartRun(const TiledRasterSource& reference_source, const TiledRasterSource& moving_source,
          const TiledMeasureOptions& tiled_options)
      : reference(reference_source), moving(moving_source), options(tiled_options),
        masked(tiled_options.measure.weight == WeightMode::kMask),
        shift{moving_source.origin[0] - reference_source.origin[0],
              moving_source.origin[1] - reference_source.origin[1]} {
    tile_options = options.measure;
    tile_options.keep_node_gaps = true;
    tile_options.allow_empty_overlap = true;
    tile_options.on_progress = nullptr;
  }

  // μ at a node as Measure has it (weights.h): the mask in the reference's
  // local frame, the moving nodes shifted into it by the same sums. Made per
  // tile as Measure makes it: an exclude mask's enclosing ring goes around
  // the tile's reference samples, and every node weighed lies among them.
  double WeightAt(const Point2& p) const { return masked && !InsideMask(tile_mask, p) ? 0.0 : 1.0; }

  void Resume(const TiledPartial& state) {
    for (const TiledBorderNode& n : state.border) {
      if (n.owned) {
        owned_top.push_back(n);
      } else {
        border[NodeKey(n.column, n.row, reference.columns)] = {n.dz, n.area};
      }
    }
    for (const TiledSharedNode& n : state.shared) {
      shared[NodeKey(n.column, n.row, moving.columns)] = {n.dz, n.weight, n.tile_row};
    }
  }

  // The state after the rows done: the maps as lists (sorted: reproducible).
  void Snapshot(TiledPartial* out) const {
    out->border = owned_top;
    for (const auto& [k, node] : border) {
      out->border.push_back({static_cast<int32_t>(k % reference.columns),
                             static_cast<int32_t>(k / reference.columns), node.dz, node.area, 0.0,
                             false});
    }
    out->shared.clear();
    for (const auto& [k, node] : shared) {
      out->shared.push_back({static_cast<int32_t>(k % moving.columns),
                             static_cast<int32_t>(k / moving.columns), node.dz, node.weight,
                             node.tile_row});
    }
    std::sort(out->border.begin(), out->border.end(), [](const auto& p, const auto& q) {
      return std::make_pair(p.row, p.column) < std::make_pair(q.row, q.column);
    });
    std::sort(out->shared.begin(), out->shared.end(), [](const auto& p, const auto& q) {
      return std::make_pair(p.row, p.column) < std::make_pair(q.row, q.column);
    });
  }

  // The moving window under the tile's complete cells (plus the margin).
  SampleWindow MovingWindow(const Surface& a, const WindowIndex& index, int32_t c0, int32_t c1, int32_t r0,
                            int32_t r1) const {
    XyBox box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    int32_t v[4];
    for (int32_t r = r0; r < r1; ++r) {
      for (int32_t c = c0; c < c1; ++c) {
        if (!index.Corners(c, r, v)) continue;
        for (int32_t i : v) {
          const double x = a.xy[i].x + reference.origin[0], y = a.xy[i].y + reference.origin[1];
          box = {std::min(box.x_min, x), std::min(box.y_min, y), std::max(box.x_max, x),
                 std::max(box.y_max, y)};
        }
      }
    }
    return ClipWindow(moving.cover(box), options.margin, moving.columns, moving.rows);
  }

  // The tile's Measure against the moving window: its sums, the tile's dz
  // and node-area parts, and the moving nodes (one tile each, but those
  // exactly on its border edges, listed in `shared`).
  void MeasureAgainstMoving(const Surface& a, const WindowIndex& index, const SampleWindow& window,
                            const SampleWindow& wb, int64_t ty, std::vector<double>* dz, std::vector<double>* area,
                            TiledPartial* part) {
    const Surface b = ReadChecked(moving, wb);
    const WindowIndex index_b(b, wb);
    int64_t cells_b = 0;
    CompleteCellArea(b, index_b, wb.column, wb.column + wb.columns - 1, wb.row, wb.row + wb.rows - 1,
                     &cells_b);
    if (cells_b == 0) return;
    const MeasureSummary s = Measure(a, b, tile_options);
    ++part->stats.tiles_measured;
    part->sums.AddTile(s);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::size_t o = index.Offset(a.raster_cell[i].column, a.raster_cell[i].row);
      (*dz)[o] = s.dz_a[i];
      (*area)[o] = s.node_area_a[i];
    }
    const TileBorder edges(a, index, window);
    for (std::size_t j = 0; j < b.size(); ++j) {
      if (!std::isfinite(s.dz_b[j])) continue;
      const Point2 p{b.xy[j].x + shift[0], b.xy[j].y + shift[1]};
      const double w = WeightAt(p);
      if (!edges.Holds(p)) {
        part->sums.AddNode(s.dz_b[j], w);
        continue;
      }
      const auto inserted = shared.emplace(NodeKey(b.raster_cell[j].column, b.raster_cell[j].row, moving.columns),
                                           SharedNode{s.dz_b[j], w, ty});
      ++(inserted.second ? part->stats.shared_moving_nodes : part->stats.merged_moving_nodes);
    }
  }

  // The owned block's DoD, final now (border nodes gather the parts of every
  // tile holding them; in row-major order the owned block is complete), and
  // its nodes into the sums (the band's shared first row: listed instead).
  TileDod OwnedDod(const Surface& a, const WindowIndex& index, const SampleWindow& window,
                   const SampleWindow& owned, const std::vector<double>& dz, const std::vector<double>& area,
                   bool top_shared, TiledSums* totals) {
    const int32_t c0 = window.column, r0 = window.row;
    const int32_t c1 = c0 + window.columns - 1, r1 = r0 + window.rows - 1;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const RasterCell& cell = a.raster_cell[i];
      if (cell.column != c0 && cell.column != c1 && cell.row != r0 && cell.row != r1) continue;
      const std::size_t o = index.Offset(cell.column, cell.row);
      if (!std::isfinite(dz[o]) && area[o] == 0.0) continue;
      BorderNode& node = border[NodeKey(cell.column, cell.row, reference.columns)];
      if (!std::isfinite(node.dz)) node.dz = dz[o];
      node.area += area[o];
    }
    TileDod dod;
    dod.window = owned;
    dod.dz.assign(static_cast<std::size_t>(owned.columns) * owned.rows, kNaN);
    dod.node_area.assign(dod.dz.size(), 0.0);
    for (int32_t r = owned.row; r < owned.row + owned.rows; ++r) {
      for (int32_t c = owned.column; c < owned.column + owned.columns; ++c) {
        const int32_t i = index.At(c, r);
        if (i < 0) continue;
        ++totals->sum.n_points_a;
        const std::size_t o = index.Offset(c, r);
        double d = dz[o], node_area = area[o];
        if (c == c0 || c == c1 || r == r0 || r == r1) {
          const auto it = border.find(NodeKey(c, r, reference.columns));
          d = kNaN, node_area = 0.0;
          if (it != border.end()) {
            d = it->second.dz;
            node_area = it->second.area;
            border.erase(it);
          }
        }
        const std::size_t out = static_cast<std::size_t>(r - owned.row) * owned.columns + (c - owned.column);
        dod.dz[out] = d;  // on a shared top row, the merge may settle it (TiledDodPatch)
        dod.node_area[out] = node_area;
        if (top_shared && r == r0) {
          owned_top.push_back({c, r, d, node_area, WeightAt(a.xy[i]), true});
        } else if (std::isfinite(d)) {
          totals->AddNode(d, WeightAt(a.xy[i]));
          if (options.budget) {
            totals->budget.AddNode(d, node_area, options.budget_sigma_dod, options.budget_threshold);
          }
        }
      }
    }
    return dod;
  }

  // Tile (tx, ty): its reference window, its measure and its DoD block.
  void Tile(int64_t tx, int64_t ty, int64_t nx, bool top_shared, TiledPartial* part) {
    SampleWindow window, owned;
    TileWindows(reference.columns, reference.rows, options.tile, tx, ty, &window, &owned);
    const int32_t c0 = window.column, r0 = window.row;
    const int32_t c1 = c0 + window.columns - 1, r1 = r0 + window.rows - 1;
    const Surface a = ReadChecked(reference, window);
    const WindowIndex index(a, window);
    if (masked && !a.xy.empty()) {
      tile_mask = MakeMaskRegion(options.measure.mask, options.measure.mask_mode,
                                 {reference.origin[0], reference.origin[1]}, a.xy);
    }
    TiledSums& totals = part->sums;
    ++part->stats.tiles;
    int64_t cells = 0;
    totals.domain_area_a += CompleteCellArea(a, index, c0, c1, r0, r1, &cells);
    totals.complete_cells_a += cells;
    MergeHull(TileHull(a, ExecutionFor(options.measure.threads)), &totals.hull_a);
    // The tile's own DoD: dz and its part of each node's area.
    const std::size_t n = static_cast<std::size_t>(window.columns) * window.rows;
    std::vector<double> dz(n, kNaN), area(n, 0.0);
    const SampleWindow wb = cells > 0 ? MovingWindow(a, index, c0, c1, r0, r1) : SampleWindow{};
    if (!wb.empty()) MeasureAgainstMoving(a, index, window, wb, ty, &dz, &area, part);
    TileDod dod = OwnedDod(a, index, window, owned, dz, area, top_shared, &totals);
    dod.tile = ty * nx + tx;
    if (options.on_tile) options.on_tile(dod);
  }

  const TiledRasterSource& reference;
  const TiledRasterSource& moving;
  const TiledMeasureOptions& options;
  MeasureOptions tile_options;
  const bool masked;
  MaskRegion tile_mask;
  const double shift[2];
  std::unordered_map<int64_t, BorderNode> border;  // reference nodes, by NodeKey
  std::unordered_map<int64_t, SharedNode> shared;  // moving nodes, likewise
  std::vector<TiledBorderNode> owned_top;          // the band's first row, for the merge
};

}  // namespace

TiledPartial MeasureTiledPart(const TiledRasterSource& reference, const TiledRasterSource& moving,
                              const TiledMeasureOptions& options, int32_t shard, int32_t shards,
                              const TiledPartial* resume) {
  CheckOptions(reference, moving, options);
  if (shards < 1 || shard < 1 || shard > shards) {
    throw InputError("tiled measure: part " + std::to_string(shard) + " of " +
                     std::to_string(shards) + " does not exist");
  }
  PartRun run(reference, moving, options);
  const int64_t nx = Tiles(reference.columns, options.tile), ny = Tiles(reference.rows, options.tile);
  TiledPartial part;
  part.shard = shard;
  part.shards = shards;
  part.tile = options.tile;
  part.tile_rows = ny;
  part.moving_tile_rows = Tiles(moving.rows, options.tile);
  TiledBand(ny, shard, shards, &part.first_row, &part.band_end_row);
  TiledBand(part.moving_tile_rows, shard, shards, &part.moving_first_row, &part.moving_end_row);
  part.end_row = part.first_row;
  part.budget = options.budget;
  part.budget_sigma_dod = options.budget_sigma_dod;
  part.budget_threshold = options.budget_threshold;
  if (resume != nullptr) {
    if (resume->shard != shard || resume->shards != shards || resume->tile != part.tile ||
        resume->tile_rows != ny || resume->moving_tile_rows != part.moving_tile_rows ||
        resume->first_row != part.first_row || resume->end_row < part.first_row ||
        resume->end_row > part.band_end_row || resume->budget != part.budget ||
        resume->budget_sigma_dod != part.budget_sigma_dod || resume->budget_threshold != part.budget_threshold) {
      throw InputError("tiled measure: the state to resume is of another run or part");
    }
    part.end_row = resume->end_row;
    part.sums = resume->sums;
    part.stats = resume->stats;
    run.Resume(*resume);
  }
  const int64_t keep = part.first_row > 0 ? part.first_row : -1;  // FlushShared
  TiledProgress progress{(part.end_row - part.first_row) * nx,
                         (part.band_end_row - part.first_row) * nx +
                             (part.moving_end_row - part.moving_first_row) *
                                 Tiles(moving.columns, options.tile),
                         (part.end_row - part.first_row) * nx};
  for (int64_t ty = part.end_row; ty < part.band_end_row; ++ty) {
    // The band's first sample row is another part's too: listed, not counted.
    const bool top_shared = ty == part.first_row && part.first_row > 0;
    for (int64_t tx = 0; tx < nx; ++tx) {
      run.Tile(tx, ty, nx, top_shared, &part);
      ++progress.done;
      if (options.on_progress) options.on_progress(progress);
    }
    FlushShared(&run.shared, ty, keep, &part.sums);  // keeps the list to two rows of tiles
    part.end_row = ty + 1;
    if (options.on_row && part.end_row < part.band_end_row) {
      run.Snapshot(&part);
      options.on_row(part);
    }
  }
  if (part.band_end_row == ny) FlushShared(&run.shared, ny, keep, &part.sums);
  run.Snapshot(&part);
  if (options.on_row && part.band_end_row > part.first_row) options.on_row(part);

  MovingPass(moving, options, part.moving_first_row, part.moving_end_row, &part.sums, &progress);
  part.moving_done = true;
  return part;
}

MeasureSummary MeasureTiled(const TiledRasterSource& reference, const TiledRasterSource& moving,
                            const TiledMeasureOptions& options, TiledMeasureStats* stats) {
  const Clock::time_point start = Clock::now();
  const TiledPartial part = MeasureTiledPart(reference, moving, options, 1, 1);
  if (stats != nullptr) *stats = part.stats;
  MeasureSummary summary = FinishTiled(part.sums, options.measure, reference.source, moving.source);
  summary.timings.total = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

Surface RasterBlockToSurface(const std::array<double, 6>& gt, const SampleWindow& window,
                             const double* values, std::size_t count, const std::array<double, 3>& origin,
                             const std::string& source, int threads) {
  if (count != static_cast<std::size_t>(std::max(window.columns, 0)) *
                   static_cast<std::size_t>(std::max(window.rows, 0))) {
    throw InputError((source.empty() ? std::string("raster") : source) + ": " + std::to_string(count) +
                     " values for a window of " + std::to_string(window.columns) + " x " +
                     std::to_string(window.rows));
  }
  Surface s = GridCellsToSurface(gt, window.column, window.row, window.columns, window.rows, values, &origin,
                                 1.0, nullptr, threads);
  s.source = source;
  return s;
}

std::array<double, 3> RasterOrigin(const std::array<double, 6>& g, int32_t columns, int32_t rows) {
  return {std::round(g[0] + 0.5 * (columns * g[1] + rows * g[2])),
          std::round(g[3] + 0.5 * (columns * g[4] + rows * g[5])), 0.0};
}

std::function<SampleWindow(const XyBox&)> AffineGridCover(const std::array<double, 6>& gt,
                                                          int32_t columns, int32_t rows) {
  return [gt, columns, rows](const XyBox& box) -> SampleWindow {
    const double det = gt[1] * gt[5] - gt[2] * gt[4];
    if (det == 0.0 || !std::isfinite(det)) return {};
    double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo;
    for (const double x : {box.x_min, box.x_max}) {
      for (const double y : {box.y_min, box.y_max}) {
        const double dx = x - gt[0], dy = y - gt[3];
        const double u = (gt[5] * dx - gt[2] * dy) / det;  // pixel-is-area column coordinate
        const double v = (gt[1] * dy - gt[4] * dx) / det;
        u_lo = std::min(u_lo, u), u_hi = std::max(u_hi, u);
        v_lo = std::min(v_lo, v), v_hi = std::max(v_hi, v);
      }
    }
    // Samples sit at u = c + 0.5; the cells meeting [u_lo, u_hi] have corner
    // samples floor(u_lo - 0.5) .. ceil(u_hi - 0.5); one more for rounding.
    auto clamp = [](double value, int32_t n) {
      return static_cast<int64_t>(std::min(std::max(value, -2.0), n + 2.0));
    };
    const int64_t c0 = std::max<int64_t>(clamp(std::floor(u_lo - 0.5), columns) - 1, 0);
    const int64_t c1 = std::min<int64_t>(clamp(std::ceil(u_hi - 0.5), columns) + 1, columns - 1);
    const int64_t r0 = std::max<int64_t>(clamp(std::floor(v_lo - 0.5), rows) - 1, 0);
    const int64_t r1 = std::min<int64_t>(clamp(std::ceil(v_hi - 0.5), rows) + 1, rows - 1);
    if (!(std::isfinite(u_lo) && std::isfinite(u_hi) && std::isfinite(v_lo) &&
          std::isfinite(v_hi)) || c1 < c0 || r1 < r0) {
      return {};
    }
    return {static_cast<int32_t>(c0), static_cast<int32_t>(r0), static_cast<int32_t>(c1 - c0 + 1),
            static_cast<int32_t>(r1 - r0 + 1)};
  };
}

// Per reference cell while a tile is measured: the two windows' samples and
// meshes, the overlay and the per-node outputs. Measured with the peak RSS
// of tiles of 100-512 cells (600-650 bytes), with room to spare.
constexpr double kBytesPerCell = 700;

double TileBytes(int32_t tile) { return kBytesPerCell * static_cast<double>(tile) * tile; }

int32_t TileForMemory(double bytes) {
  const double side = std::floor(std::sqrt(std::max(bytes, 0.0) / kBytesPerCell));
  return static_cast<int32_t>(std::clamp(side, 16.0, 32768.0));
}

double ParseMemorySize(const std::string& text, const std::string& where) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double number = std::strtod(begin, &end);
  std::string unit(end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();                  // "MB", "GiB"
  if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();                      // "Mi", "Gi"
  double scale = 0;
  if (unit.empty()) scale = 1;
  if (unit == "K") scale = 1024.0;
  if (unit == "M") scale = 1024.0 * 1024;
  if (unit == "G") scale = 1024.0 * 1024 * 1024;
  if (end == begin || scale == 0 || !std::isfinite(number) || number <= 0) {
    throw InputError(where + " expects a memory size such as 512M or 2G, got '" + text + "'");
  }
  const double bytes = number * scale;
  if (bytes < TileBytes(16)) {
    throw InputError(where + ": " + text + " is less than the smallest tile needs (16 x 16 cells, " +
                     std::to_string(static_cast<int64_t>(TileBytes(16) / 1024)) + " KiB)");
  }
  return bytes;
}

}  // namespace surfreg

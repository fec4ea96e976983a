#pragma once
// The measures of two raster surfaces, tile by tile (issue 24): a pair too
// large to hold at once is measured in blocks of the reference raster's
// cells, with only one tile's surfaces and overlay in memory, and the result
// equals Measure(a, b) on the whole surfaces (to rounding: sums in another
// order).
//
// Why it is exact: a raster surface is meshed on its own cells and its data
// domain is exactly its complete cells (grid_mesh.h, domain.h), so a window
// of cells has the same grid triangles as the whole raster there. A tile is
// a block of the reference's cells (its samples c0..c1, r0..r1, the far
// corner row and column included); its domain is exactly that block's
// complete cells. The moving surface is read over the cells covering the
// tile's box plus a margin, so all its triangles over the tile are there.
// Then the tiles' overlay cells partition the whole overlay: volumes and
// areas add up. The rest is bookkeeping:
// - ρ'd counts each node of G1 ∪ G2 in Ω once. A reference node inside a
//   tile's block is in one tile only; one on the block's border is in two or
//   four, and is in Ω if any of them says so (its gap is the same in each;
//   its node area is the sum of their parts). A moving node counted by two
//   tiles lies exactly on their shared border (in two closed cells on
//   either side of it): the nodes exactly on a tile's border edges (exact
//   orientation test) are kept in a short list keyed by (column, row) and
//   counted once at the end; every other counted node has one tile.
// - the domain areas and hulls: the reference's from the tiles (a
//   partition of its cells), the moving one's from a second pass over its
//   own blocks of cells (its windows overlap); the hulls as the hull of the
//   tiles' hull vertices.
// Tiles are processed in row-major order, so a block of the DoD is final
// once its tile is done (on_tile); the bookkeeping is O(raster width + tile).
//
// A part of the tiles (tiled_partial.h) is measured by MeasureTiledPart,
// and the parts merged by MergeTiledPartials.
//
// Limits: uniform or mask weights, the overlay volume, the data domain
// (per-point weights, the union mode and the hull domain are not local and
// are refused). A folded grid (grid_mesh.h) may differ at the folds: there
// a whole raster drops cells next to a fold in another tile.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "measure/measures.h"
#include "measure/surface.h"
#include "terrain/tiled_partial.h"

namespace surfreg {

// A block of a raster's samples (pixels): columns [column, column + columns)
// and rows [row, row + rows), in the whole raster's numbering.
struct SampleWindow {
  int32_t column = 0, row = 0;
  int32_t columns = 0, rows = 0;
  bool empty() const { return columns <= 0 || rows <= 0; }
};

// An axis-aligned box in input coordinates (the data's CRS, not local).
struct XyBox {
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;
};

// One raster as the tiled measure reads it, a window at a time.
struct TiledRasterSource {
  int32_t columns = 0, rows = 0;  // size of the whole raster in samples (pixels)
  // The origin of every Surface `read` returns: fixed, so that each window's
  // local coordinates are the very doubles of an untiled read with it.
  std::array<double, 3> origin = {0.0, 0.0, 0.0};
  std::string source;  // for messages, as Surface::source
  // The valid samples of a window (never empty, inside the raster), with
  // Surface::origin == origin and raster_cell in the whole raster's
  // numbering; it may be empty of samples. E.g. RasterBlockToSurface.
  std::function<Surface(const SampleWindow&)> read;
  // Moving surface only: a window of samples whose cells cover `box` (a
  // larger one is fine; it is clipped to the raster and widened by
  // TiledMeasureOptions::margin). E.g. AffineGridCover.
  std::function<SampleWindow(const XyBox&)> cover;
};

// The DoD of one tile's reference samples, final (on_tile): row-major over
// `window`; NaN / 0 at samples not in Ω and at nodata. The windows of all
// tiles partition the reference's samples.
struct TileDod {
  int64_t tile = 0;     // row-major index
  SampleWindow window;  // the samples this tile owns
  std::vector<double> dz;         // as MeasureSummary::dz_a
  std::vector<double> node_area;  // as MeasureSummary::node_area_a (whole, not the tile's part)
};

struct TiledProgress {
  int64_t done = 0, total = 0;  // tiles (the moving surface's area pass included)
  int64_t resumed = 0;          // of `done`, done before a resume (not timed now)
};

struct TiledMeasureOptions {
  // keep_node_gaps is ignored (see on_tile); allow_empty_overlap is set per
  // tile. parallel: each tile's Measure on two threads.
  MeasureOptions measure;
  int32_t tile = 512;   // tile side in reference cells (> 0)
  int32_t margin = 2;   // samples added around each moving window (>= 1)
  // A change budget over the reference's nodes (terrain/change_budget.h,
  // TiledSums::budget) with one σ_DoD for every node (the DEMs' σ given as
  // numbers) and its threshold L = max(lod, t σ_DoD).
  bool budget = false;
  double budget_sigma_dod = 0, budget_threshold = 0;
  std::function<void(const TileDod&)> on_tile;
  std::function<void(const TiledProgress&)> on_progress;
  // MeasureTiledPart: the part's state after each of its tile rows (once the
  // DoD of its tiles went to on_tile), e.g. to checkpoint it for a resume.
  std::function<void(const TiledPartial&)> on_row;
};


// The measures of `moving` against `reference`, tile by tile: the
// MeasureSummary of Measure(reference, moving, options.measure) on the
// whole surfaces, except dz_a and node_area_a (streamed through on_tile),
// n_duplicates (0), walk_steps and timings (summed over the tiles).
// Throws InputError for invalid options (tile or margin < 1, per-point
// weights, the union mode, the hull domain, no `cover` callback), and as
// Measure does when a surface has no data domain or the whole overlap is
// empty or a sliver; never for one tile alone.
MeasureSummary MeasureTiled(const TiledRasterSource& reference, const TiledRasterSource& moving,
                            const TiledMeasureOptions& options,
                            TiledMeasureStats* stats = nullptr);

// Part `shard` of `shards` (1-based) of MeasureTiled: the band of the
// tiles' rows TiledBand gives it (and of the moving raster's for its area
// pass), complete. The DoD of its tiles goes to on_tile as MeasureTiled's;
// but on the band's first sample row when another part measures the band
// above: there the merge may settle a value (TiledDodPatch). With `resume`
// (a state on_row gave for the same sources, options and part) it goes on
// after that state's rows. Throws as MeasureTiled, but for the overlap
// (FinishTiled checks it on the whole).
TiledPartial MeasureTiledPart(const TiledRasterSource& reference, const TiledRasterSource& moving,
                              const TiledMeasureOptions& options, int32_t shard, int32_t shards,
                              const TiledPartial* resume = nullptr);

// The valid samples of a window of an affine raster grid (GDAL's
// pixel-is-area geotransform: a sample at its cell's centre, as
// io/raster_io.h), computed as RasterToSurface does so that the
// coordinates equal an untiled read's bit for bit given the same origin.
// `values` holds `count` = window.columns * window.rows heights, row-major,
// NaN (or any non-finite value) for nodata.
Surface RasterBlockToSurface(const std::array<double, 6>& geotransform, const SampleWindow& window,
                             const double* values, std::size_t count, const std::array<double, 3>& origin,
                             const std::string& source = "", int threads = 1);

// The origin a tiled measure gives both rasters: the centre of the
// reference's extent (columns x rows samples of pixel-is-area geotransform
// `gt`), rounded to whole units as MakeSurface rounds, and z = 0 (a fixed
// origin needs no pass over the heights).
std::array<double, 3> RasterOrigin(const std::array<double, 6>& gt, int32_t columns, int32_t rows);

// A `cover` for an affine raster grid of columns x rows samples: the
// samples whose cells meet the box, plus one on each side for rounding.
std::function<SampleWindow(const XyBox&)> AffineGridCover(const std::array<double, 6>& geotransform,
                                                          int32_t columns, int32_t rows);

// Bytes a tile of side `tile` (cells) takes while measured: both windows,
// their meshes and the overlay (about 700 bytes per reference cell, measured
// on the tests' pairs), and the tile side that fits in `bytes`.
double TileBytes(int32_t tile);
int32_t TileForMemory(double bytes);

// Parses a memory size: "512M", "2G", "1.5GiB", "800000000" (bytes).
// Throws InputError starting with `where`.
double ParseMemorySize(const std::string& text, const std::string& where);

}  // namespace surfreg

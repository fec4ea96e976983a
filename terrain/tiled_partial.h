#pragma once
// A tiled measure in parts (issue 24): the state of MeasureTiled over a band
// of tile rows, exact, so that parts measured apart (shards: `--shard K/N`)
// or one after the other (a run resumed after a kill) add up to the very
// result of one uninterrupted run.
//
// A band is the tile rows [first_row, end_row) of the reference (shards cut
// the rows into contiguous bands: the state crossing a band's edge is then
// one row of samples, not a whole border around scattered tiles) and the
// moving raster's tile rows [moving_first_row, moving_end_row) for its own
// area pass. What crosses a band's edge (tiled_measure.h's bookkeeping):
// - the reference nodes on the sample row two bands share: the band below
//   owns them and lists them (`owned`, with μ) instead of counting them, the
//   band above lists its parts of them (dz, node area); the merge combines
//   the two and counts each node once;
// - the moving nodes exactly on tile borders that a tile of the band's first
//   or last tile row listed: listed again here, counted once by the merge.
// Sums (volumes, areas, counts) are added; hulls are the hull of the hulls.
#include <cstdint>
#include <string>
#include <vector>

#include "terrain/change_budget.h"
#include "measure/convex_hull.h"  // the hulls the parts carry
#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg {

// The sums that make up a MeasureSummary, over tiles.
struct TiledSums {
  // rho_d, overlap_area, weight_integral, signed_volume, volume_above,
  // volume_below, fill_detected, cut_detected, fill_area, cut_area,
  // n_cells, walk_steps, n_points_a, n_points_b, n_overlap_nodes, timings.
  MeasureSummary sum;
  double gap_sum = 0, node_weight = 0;  // ρ'd: Σ μ|d| and Σ μ over the nodes
  double domain_area_a = 0, domain_area_b = 0;
  int64_t complete_cells_a = 0, complete_cells_b = 0;
  std::vector<Point2> hull_a, hull_b;  // convex hulls (local coordinates)
  ChangeBudgetSums budget;             // over the reference's nodes, with a budget

  void AddNode(double dz, double weight);
  void AddTile(const MeasureSummary& s);
  void Add(const TiledSums& other);  // sums, and the hull of the hulls
};

// A reference node on a band's first or last sample row.
struct TiledBorderNode {
  int32_t column = 0, row = 0;
  double dz = 0;       // NaN unless a tile of the band has it in Ω
  double area = 0;     // the band's tiles' part of its node area
  double weight = 0;   // μ at it (owned nodes)
  bool owned = false;  // on the band's first row: the band owns it (a valid sample)
};

// A moving node exactly on a tile border, not counted yet.
struct TiledSharedNode {
  int32_t column = 0, row = 0;  // in the moving raster
  double dz = 0, weight = 0;
  int64_t tile_row = 0;  // the reference tile row that listed it
};

struct TiledMeasureStats {
  int64_t tiles = 0;           // reference tiles
  int64_t tiles_measured = 0;  // of them, with a Measure (data in both)
  int64_t shared_moving_nodes = 0;  // moving nodes on tile borders (listed)
  int64_t merged_moving_nodes = 0;  // of them, counted by two tiles (counted once)
};

struct TiledPartial {
  int32_t shard = 1, shards = 1;     // part K of N (1 of 1: the whole run)
  int32_t tile = 0;                  // tile side, cells
  int64_t tile_rows = 0, moving_tile_rows = 0;  // of the whole rasters
  int64_t first_row = 0, band_end_row = 0;      // the band of reference tile rows
  int64_t end_row = 0;  // rows done: [first_row, end_row); < band_end_row while running
  int64_t moving_first_row = 0, moving_end_row = 0;
  bool moving_done = false;  // the moving raster's area pass over its band
  // The change budget's one σ_DoD and threshold (TiledMeasureOptions).
  bool budget = false;
  double budget_sigma_dod = 0, budget_threshold = 0;
  TiledSums sums;
  TiledMeasureStats stats;
  std::vector<TiledBorderNode> border;
  std::vector<TiledSharedNode> shared;

  bool complete() const { return end_row == band_end_row && moving_done; }
};

// The band of part K of N (1-based) of `rows` tile rows: [*first, *end),
// contiguous, in order, covering all rows (empty when N > rows).
void TiledBand(int64_t rows, int32_t shard, int32_t shards, int64_t* first, int64_t* end);

// A DoD value the merge settles: the sample row two bands share.
struct TiledDodPatch {
  int32_t column = 0, row = 0;
  double dz = 0;
};

// Combines the complete parts 1..N of one run (any order) into the whole
// run's state (shard 1 of 1, no border lists) and the DoD values of the
// rows that bands share (*patches, row-major). Throws InputError naming
// the part ("part K/N: ...") when one is missing, repeated, unfinished or
// of another run (other tile or raster sizes).
TiledPartial MergeTiledPartials(std::vector<TiledPartial> parts, std::vector<TiledDodPatch>* patches);

// The MeasureSummary of a whole run's sums (as MeasureTiled returns it);
// throws InputError as Measure does when a surface has no data domain or
// the overlap is empty or a sliver. Names are for messages ("" = "surface A").
MeasureSummary FinishTiled(const TiledSums& sums, const MeasureOptions& options,
                           const std::string& name_a, const std::string& name_b);

}  // namespace surfreg

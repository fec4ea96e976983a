// MeasureTiled (terrain/tiled_measure.h) against Measure on the whole
// surfaces: two synthetic rasters with nodata holes (one larger than a
// tile) and a known change, on different grids and on one grid, for tile
// sizes from one cell to more than the raster.
#include "terrain/tiled_measure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "measure/measures.h"
#include "terrain/tiled_partial.h"
#include "tests/testing/raster_grid.h"

namespace surfreg {
namespace {

using testing::Grid;
using testing::Hole;
using testing::kX0;
using testing::kY0;
using testing::MakeGrid;

// The DoD gathered from on_tile into whole-raster arrays.
struct Dod {
  std::vector<double> dz, area;
  std::vector<int32_t> seen;  // how many tiles wrote each sample
  int64_t all_nodata_tiles = 0;
};

TiledMeasureOptions WithDod(TiledMeasureOptions options, const Grid& a, Dod* dod) {
  const std::size_t n = a.values.size();
  dod->dz.assign(n, std::nan(""));
  dod->area.assign(n, 0.0);
  dod->seen.assign(n, 0);
  options.on_tile = [&a, dod](const TileDod& t) {
    ASSERT_EQ(t.dz.size(), static_cast<std::size_t>(t.window.columns) * t.window.rows);
    bool any = false;
    for (int32_t r = 0; r < t.window.rows; ++r) {
      for (int32_t c = 0; c < t.window.columns; ++c) {
        const std::size_t in = static_cast<std::size_t>(r) * t.window.columns + c;
        const std::size_t out =
            static_cast<std::size_t>(t.window.row + r) * a.columns + t.window.column + c;
        dod->dz[out] = t.dz[in];
        dod->area[out] = t.node_area[in];
        ++dod->seen[out];
        any = any || std::isfinite(a.values[out]);
      }
    }
    if (!any) ++dod->all_nodata_tiles;
  };
  return options;
}

// |got - want| <= tolerance * max(|want|, scale).
void Near(const char* what, double want, double got, double scale, double tolerance = 1e-9) {
  EXPECT_LE(std::fabs(got - want), tolerance * std::max(std::fabs(want), scale))
      << what << ": untiled " << want << ", tiled " << got;
}

double MaxRelative(double want, double got, double scale) {
  return std::fabs(got - want) / std::max(std::fabs(want), scale);
}

// Every quantity the untiled Measure reports, and the DoD per sample.
double ExpectSame(const MeasureSummary& m, const MeasureSummary& t, const Surface& whole_a,
                  const Grid& a, const Dod& dod) {
  const double volume = m.rho_d, area = m.domain_area_a;
  Near("rho_d", m.rho_d, t.rho_d, volume);
  Near("rho_d_axial", m.rho_d_axial, t.rho_d_axial, m.rho_d_axial);
  Near("rho_s", m.rho_s, t.rho_s, m.rho_s);
  Near("overlap_area", m.overlap_area, t.overlap_area, area);
  Near("weight_integral", m.weight_integral, t.weight_integral, area);
  Near("mean_abs_dz", m.mean_abs_dz, t.mean_abs_dz, m.mean_abs_dz);
  Near("signed_volume", m.signed_volume, t.signed_volume, volume);
  Near("volume_above", m.volume_above, t.volume_above, volume);
  Near("volume_below", m.volume_below, t.volume_below, volume);
  Near("fill_detected", m.fill_detected, t.fill_detected, volume);
  Near("cut_detected", m.cut_detected, t.cut_detected, volume);
  Near("fill_area", m.fill_area, t.fill_area, area);
  Near("cut_area", m.cut_area, t.cut_area, area);
  Near("domain_area_a", m.domain_area_a, t.domain_area_a, area);
  Near("domain_area_b", m.domain_area_b, t.domain_area_b, area);
  Near("hull_area_a", m.hull_area_a, t.hull_area_a, area);
  Near("hull_area_b", m.hull_area_b, t.hull_area_b, area);
  Near("excluded_area_a", m.excluded_area_a, t.excluded_area_a, area);
  Near("excluded_area_b", m.excluded_area_b, t.excluded_area_b, area);
  EXPECT_EQ(m.level_of_detection, t.level_of_detection);
  EXPECT_EQ(m.n_overlap_nodes, t.n_overlap_nodes);
  EXPECT_EQ(m.n_cells, t.n_cells);
  EXPECT_EQ(m.n_points_a, t.n_points_a);
  EXPECT_EQ(m.n_points_b, t.n_points_b);
  EXPECT_TRUE(t.dz_a.empty() && t.node_area_a.empty());
  double worst = std::max({MaxRelative(m.rho_d, t.rho_d, volume),
                           MaxRelative(m.signed_volume, t.signed_volume, volume),
                           MaxRelative(m.overlap_area, t.overlap_area, area),
                           MaxRelative(m.rho_d_axial, t.rho_d_axial, m.rho_d_axial),
                           MaxRelative(m.fill_detected, t.fill_detected, volume),
                           MaxRelative(m.hull_area_b, t.hull_area_b, area),
                           MaxRelative(m.domain_area_b, t.domain_area_b, area)});
  // The DoD: each sample written by one tile; NaN exactly where untiled.
  int bad = 0;
  for (std::size_t i = 0; i < whole_a.size(); ++i) {
    const RasterCell& cell = whole_a.raster_cell[i];
    const std::size_t k = static_cast<std::size_t>(cell.row) * a.columns + cell.column;
    const double want = m.dz_a[i], got = dod.dz[k];
    const bool ok = std::isnan(want) ? std::isnan(got)
                                     : std::fabs(got - want) <= 1e-12 * std::max(std::fabs(want), 1.0);
    const bool area_ok =
        std::fabs(dod.area[k] - m.node_area_a[i]) <= 1e-12 * std::max(m.node_area_a[i], 1.0);
    if ((!ok || !area_ok) && ++bad <= 5) {
      ADD_FAILURE() << "sample (" << cell.column << ", " << cell.row << "): dz " << want << " / "
                    << got << ", area " << m.node_area_a[i] << " / " << dod.area[k];
    }
  }
  EXPECT_EQ(bad, 0);
  for (std::size_t k = 0; k < dod.seen.size(); ++k) {
    if (dod.seen[k] != 1 && ++bad <= 5) ADD_FAILURE() << "sample " << k << " written " << dod.seen[k];
  }
  return worst;
}

MeasureOptions Options() {
  MeasureOptions o;
  o.detect_change = true;
  o.level_of_detection = 0.05;
  return o;
}

MeasureSummary Untiled(const Grid& a, const Grid& b, MeasureOptions options) {
  options.keep_node_gaps = true;
  return Measure(a.Whole(), b.Whole(), options);
}

// Compares one tiled run; returns the largest relative difference.
double Compare(const Grid& a, const Grid& b, const MeasureSummary& untiled, int32_t tile,
               MeasureOptions measure, TiledMeasureStats* stats = nullptr, Dod* dod_out = nullptr) {
  SCOPED_TRACE("tile " + std::to_string(tile));
  TiledMeasureOptions options;
  options.measure = measure;
  options.tile = tile;
  TiledProgress last;
  options.on_progress = [&last](const TiledProgress& p) { last = p; };
  Dod dod;
  options = WithDod(options, a, &dod);
  const MeasureSummary tiled = MeasureTiled(a.Source(), b.Source(), options, stats);
  EXPECT_EQ(last.done, last.total);
  EXPECT_GT(last.total, 0);
  const double worst = ExpectSame(untiled, tiled, a.Whole(), a, dod);
  if (dod_out != nullptr) *dod_out = std::move(dod);
  return worst;
}

const std::array<double, 6> kGridA = {kX0, 1.0, 0.0, kY0, 0.0, -1.0};

int64_t TileCount(const Grid& a, int32_t tile) {
  return ((a.columns - 1 + tile - 1) / tile) * ((a.rows - 1 + tile - 1) / tile);
}

// Parts 1..N measured one by one (in reverse order), merged, their DoDs
// settled by the merge's patches: the unsharded run's sums to 1e-9 and its
// DoD bit for bit. Returns the merged summary.
MeasureSummary Sharded(const Grid& a, const Grid& b, MeasureOptions measure, int32_t tile,
                       int32_t shards, const Dod& unsharded) {
  SCOPED_TRACE("tile " + std::to_string(tile) + ", " + std::to_string(shards) + " shards");
  TiledMeasureOptions options;
  options.measure = measure;
  options.tile = tile;
  Dod dod;
  options = WithDod(options, a, &dod);
  std::vector<TiledPartial> parts;
  for (int32_t k = shards; k >= 1; --k) {
    parts.push_back(MeasureTiledPart(a.Source(), b.Source(), options, k, shards));
  }
  std::vector<TiledDodPatch> patches;
  const TiledPartial whole = MergeTiledPartials(parts, &patches);
  for (const TiledDodPatch& p : patches) {
    dod.dz[static_cast<std::size_t>(p.row) * a.columns + p.column] = p.dz;
  }
  int differ = 0;
  for (std::size_t k = 0; k < dod.dz.size(); ++k) {
    const double want = unsharded.dz[k], got = dod.dz[k];
    if (!(std::isnan(want) ? std::isnan(got) : want == got) && ++differ <= 3) {
      ADD_FAILURE() << "DoD sample " << k << ": unsharded " << want << ", sharded " << got;
    }
    EXPECT_EQ(dod.seen[k], 1) << "sample " << k;
  }
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(whole.stats.tiles, TileCount(a, tile));
  return FinishTiled(whole.sums, measure, a.name, b.name);
}

// A 400 x 300 reference and a moving raster on another grid (shifted by a
// fraction of a cell, cells 1% larger and 1% smaller), with a 40-cell hole
// (more than a tile of 37) and another origin.
TEST(TiledMeasureTest, OtherGridEqualsUntiled) {
  const Grid a = MakeGrid(400, 300, kGridA, {kX0 + 200, kY0 - 150, 0}, false,
                          {{150, 120, 40}, {330, 60, 8}}, 1u, "a.tif");
  const Grid b = MakeGrid(400, 305, {kX0 + 0.37, 1.01, 0.0, kY0 - 0.23, 0.0, -0.99},
                          {kX0 + 210, kY0 - 140, 50}, true, {{260, 200, 18}}, 2u, "b.tif");
  const MeasureSummary untiled = Untiled(a, b, Options());
  ASSERT_GT(untiled.fill_detected, 0.0);
  ASSERT_GT(untiled.cut_detected, 0.0);
  double worst = 0.0;
  for (int32_t tile : {37, 128, 1000}) {
    TiledMeasureStats stats;
    worst = std::max(worst, Compare(a, b, untiled, tile, Options(), &stats));
    EXPECT_EQ(stats.tiles, ((399 + tile - 1) / tile) * ((299 + tile - 1) / tile));
  }
  RecordProperty("max_relative_difference", std::to_string(worst));
  std::printf("other grid: largest relative difference %.3g\n", worst);
}

// The same grid: every moving node is a reference node (counted once, as A's).
TEST(TiledMeasureTest, SameGridEqualsUntiled) {
  const std::array<double, 3> origin = {kX0 + 200, kY0 - 150, 0};
  const Grid a = MakeGrid(400, 300, kGridA, origin, false, {{100, 200, 30}}, 3u, "a.tif");
  const Grid b = MakeGrid(400, 300, kGridA, origin, true, {{300, 100, 45}}, 4u, "b.tif");
  const MeasureSummary untiled = Untiled(a, b, Options());
  Compare(a, b, untiled, 61, Options());
}

// A mask polygon (weights 1 inside, 0 outside), crossing tiles and holes.
TEST(TiledMeasureTest, MaskEqualsUntiled) {
  const Grid a = MakeGrid(160, 120, kGridA, {kX0 + 80, kY0 - 60, 0}, false, {{60, 50, 20}}, 5u,
                          "a.tif");
  const Grid b = MakeGrid(165, 125, {kX0 - 0.61, 0.995, 0.0, kY0 + 0.4, 0.0, -1.005},
                          {kX0 + 80, kY0 - 60, 0}, true, {}, 6u, "b.tif");
  MeasureOptions options = Options();
  options.weight = WeightMode::kMask;
  options.mask = {{{kX0 + 10.2, kY0 - 5.7}, {kX0 + 140.3, kY0 - 20.1}, {kX0 + 100.9, kY0 - 60.0},
                   {kX0 + 150.0, kY0 - 110.4}, {kX0 + 20.5, kY0 - 100.0}},
                  // a hole, across tile borders
                  {{kX0 + 40.5, kY0 - 70.2}, {kX0 + 70.1, kY0 - 70.9}, {kX0 + 55.3, kY0 - 90.4}}};
  const MeasureSummary untiled = Untiled(a, b, options);
  ASSERT_LT(untiled.weight_integral, 0.9 * untiled.overlap_area);
  for (int32_t tile : {13, 50}) Compare(a, b, untiled, tile, options);
  // The same rings as unstable areas: every tile has its own enclosing ring.
  options.mask_mode = MaskMode::kExclude;
  const MeasureSummary excluded = Untiled(a, b, options);
  ASSERT_GT(excluded.weight_integral, 0.1 * excluded.overlap_area);
  for (int32_t tile : {13, 50}) Compare(a, b, excluded, tile, options);
}

// Tiles of 1, 2 and 5 cells on a small pair: most nodes are on a tile
// border; a hole of 9 cells' radius covers whole tiles (only nodata).
TEST(TiledMeasureTest, TinyTilesEqualUntiled) {
  const Grid a = MakeGrid(48, 37, kGridA, {kX0 + 24, kY0 - 18, 0}, false, {{20, 18, 9}}, 7u, "a.tif");
  const Grid b = MakeGrid(50, 40, {kX0 + 0.29, 1.013, 0.0, kY0 - 0.41, 0.0, -0.987},
                          {kX0 + 24, kY0 - 18, 0}, true, {{40, 10, 4}}, 8u, "b.tif");
  MeasureOptions options = Options();
  options.threads = 1;  // thousands of tiny Measures: no threads each
  const MeasureSummary untiled = Untiled(a, b, options);
  for (int32_t tile : {1, 2, 5}) {
    Dod dod;
    Compare(a, b, untiled, tile, options, nullptr, &dod);
    EXPECT_GT(dod.all_nodata_tiles, 0);
  }
}

// Moving nodes exactly on the reference's grid lines (half a cell across):
// those on a tile border are counted by two tiles, and once in the result.
TEST(TiledMeasureTest, MovingNodesOnTileBordersCountOnce) {
  const std::array<double, 3> origin = {kX0 + 30, kY0 - 20, 0};
  const Grid a = MakeGrid(60, 40, kGridA, origin, false, {{30, 20, 5}}, 9u, "a.tif");
  const Grid b = MakeGrid(60, 40, {kX0 + 0.5, 1.0, 0.0, kY0, 0.0, -1.0}, origin, true, {}, 10u,
                          "b.tif");
  MeasureOptions options = Options();
  options.threads = 1;
  const MeasureSummary untiled = Untiled(a, b, options);
  for (int32_t tile : {3, 8}) {
    TiledMeasureStats stats;
    Dod dod;
    Compare(a, b, untiled, tile, options, &stats, &dod);
    EXPECT_GT(stats.merged_moving_nodes, 0);
    // And on the borders between shards' bands: counted once by the merge.
    ExpectSame(untiled, Sharded(a, b, options, tile, 4, dod), a.Whole(), a, dod);
  }
}

TEST(TiledMeasureTest, NoOverlapIsTheUntiledError) {
  const Grid a = MakeGrid(30, 20, kGridA, {kX0, kY0, 0}, false, {}, 11u, "a.tif");
  const Grid b = MakeGrid(30, 20, {kX0 + 1000.0, 1.0, 0.0, kY0, 0.0, -1.0}, {kX0, kY0, 0}, true, {},
                          12u, "b.tif");
  std::string untiled, tiled;
  try {
    Measure(a.Whole(), b.Whole(), Options());
  } catch (const InputError& e) {
    untiled = e.what();
  }
  TiledMeasureOptions options;
  options.measure = Options();
  options.tile = 7;
  try {
    MeasureTiled(a.Source(), b.Source(), options);
  } catch (const InputError& e) {
    tiled = e.what();
  }
  EXPECT_NE(untiled.find("do not overlap"), std::string::npos) << untiled;
  EXPECT_EQ(untiled, tiled);
}

TEST(TiledMeasureTest, RefusesWhatIsNotLocal) {
  const Grid a = MakeGrid(10, 10, kGridA, {kX0, kY0, 0}, false, {}, 13u, "a.tif");
  TiledMeasureOptions options;
  options.measure = Options();
  for (int32_t tile : {0, -4}) {
    options.tile = tile;
    EXPECT_THROW(MeasureTiled(a.Source(), a.Source(), options), InputError);
  }
  options.tile = 4;
  options.measure.weight = WeightMode::kPerPoint;
  EXPECT_THROW(MeasureTiled(a.Source(), a.Source(), options), InputError);
  options.measure = Options();
  options.measure.volume = VolumeMode::kUnion;
  options.measure.detect_change = false;
  EXPECT_THROW(MeasureTiled(a.Source(), a.Source(), options), InputError);
  options.measure = MeasureOptions();
  options.measure.domain.kind = DomainKind::kHull;
  EXPECT_THROW(MeasureTiled(a.Source(), a.Source(), options), InputError);
  options.measure = MeasureOptions();
  TiledRasterSource no_cover = a.Source();
  no_cover.cover = nullptr;
  EXPECT_THROW(MeasureTiled(a.Source(), no_cover, options), InputError);
}

// A window read whole is the whole surface, bit for bit.
TEST(TiledMeasureTest, BlockSurfaceIsTheWholeOnesWindow) {
  const Grid a = MakeGrid(20, 15, kGridA, {kX0 + 10, kY0 - 7, 0}, false, {{5, 5, 2}}, 14u, "a");
  const Surface whole = a.Whole();
  const Surface part = a.Source().read({3, 4, 9, 6});
  ASSERT_GT(part.size(), 0u);
  for (std::size_t i = 0; i < part.size(); ++i) {
    const RasterCell cell = part.raster_cell[i];
    const auto it = std::find_if(whole.raster_cell.begin(), whole.raster_cell.end(),
                                 [&](const RasterCell& w) {
                                   return w.column == cell.column && w.row == cell.row;
                                 });
    ASSERT_NE(it, whole.raster_cell.end());
    const std::size_t k = static_cast<std::size_t>(it - whole.raster_cell.begin());
    EXPECT_EQ(part.xy[i].x, whole.xy[k].x);
    EXPECT_EQ(part.xy[i].y, whole.xy[k].y);
    EXPECT_EQ(part.z[i], whole.z[k]);
  }
}


// --- parts: shards merged, a run resumed (terrain/tiled_partial.h) ----------

TEST(TiledPartialTest, ShardsMergeToTheUnshardedRun) {
  const Grid a = MakeGrid(120, 97, kGridA, {kX0 + 60, kY0 - 48, 0}, false, {{50, 40, 14}}, 13u,
                          "a.tif");
  const Grid b = MakeGrid(126, 100, {kX0 + 0.5, 1.0, 0.0, kY0 - 0.31, 0.0, -1.0},
                          {kX0 + 61, kY0 - 50, 0}, true, {{90, 70, 6}}, 14u, "b.tif");
  MeasureOptions options = Options();
  options.threads = 1;
  const MeasureSummary untiled = Untiled(a, b, options);
  for (int32_t tile : {9, 16, 40}) {
    Dod unsharded;
    Compare(a, b, untiled, tile, options, nullptr, &unsharded);
    for (int32_t shards : {2, 3, 4, 13}) {  // 13 > the 11 tile rows of tiles of 9: empty bands
      const MeasureSummary merged = Sharded(a, b, options, tile, shards, unsharded);
      ExpectSame(untiled, merged, a.Whole(), a, unsharded);
    }
  }
}

TEST(TiledPartialTest, MaskedShardsMergeToTheUnshardedRun) {
  const Grid a = MakeGrid(80, 70, kGridA, {kX0 + 40, kY0 - 35, 0}, false, {{30, 30, 8}}, 15u, "a.tif");
  const Grid b = MakeGrid(82, 72, {kX0 - 0.61, 0.995, 0.0, kY0 + 0.4, 0.0, -1.005},
                          {kX0 + 40, kY0 - 35, 0}, true, {}, 16u, "b.tif");
  MeasureOptions options = Options();
  options.threads = 1;
  options.weight = WeightMode::kMask;
  options.mask_mode = MaskMode::kExclude;
  options.mask = {{{kX0 + 10.2, kY0 - 5.7}, {kX0 + 70.3, kY0 - 20.1}, {kX0 + 20.5, kY0 - 60.0}}};
  const MeasureSummary untiled = Untiled(a, b, options);
  Dod unsharded;
  Compare(a, b, untiled, 12, options, nullptr, &unsharded);
  ExpectSame(untiled, Sharded(a, b, options, 12, 3, unsharded), a.Whole(), a, unsharded);
}

// A part stopped after some tile rows and resumed from the state on_row
// gave: the very sums (bit for bit) and DoD of an uninterrupted part.
TEST(TiledPartialTest, ResumedPartEqualsUninterruptedBitForBit) {
  const Grid a = MakeGrid(100, 90, kGridA, {kX0 + 50, kY0 - 45, 0}, false, {{40, 40, 12}}, 17u,
                          "a.tif");
  const Grid b = MakeGrid(104, 92, {kX0 + 0.37, 1.01, 0.0, kY0 - 0.23, 0.0, -0.99},
                          {kX0 + 52, kY0 - 44, 0}, true, {}, 18u, "b.tif");
  TiledMeasureOptions options;
  options.measure = Options();
  options.measure.threads = 1;
  options.tile = 11;
  for (int32_t shard : {1, 2}) {
    Dod whole;
    const TiledPartial full = MeasureTiledPart(a.Source(), b.Source(), WithDod(options, a, &whole),
                                               shard, 2);
    for (int64_t stop : {1, 3}) {
      Dod dod;
      TiledMeasureOptions killed = WithDod(options, a, &dod);
      TiledPartial state;
      killed.on_row = [&state, &full, stop](const TiledPartial& p) {
        if (p.end_row == full.first_row + stop) {
          state = p;
          throw InputError("killed");
        }
      };
      EXPECT_THROW(MeasureTiledPart(a.Source(), b.Source(), killed, shard, 2), InputError);
      ASSERT_EQ(state.end_row, full.first_row + stop);
      TiledMeasureOptions resumed = killed;  // the DoD gathered so far kept
      resumed.on_row = nullptr;
      const TiledPartial again = MeasureTiledPart(a.Source(), b.Source(), resumed, shard, 2, &state);
      EXPECT_EQ(again.sums.sum.rho_d, full.sums.sum.rho_d);
      EXPECT_EQ(again.sums.gap_sum, full.sums.gap_sum);
      EXPECT_EQ(again.sums.sum.signed_volume, full.sums.sum.signed_volume);
      EXPECT_EQ(again.sums.domain_area_a, full.sums.domain_area_a);
      EXPECT_EQ(again.sums.sum.n_overlap_nodes, full.sums.sum.n_overlap_nodes);
      EXPECT_EQ(again.border.size(), full.border.size());
      EXPECT_EQ(again.shared.size(), full.shared.size());
      for (std::size_t k = 0; k < dod.dz.size(); ++k) {
        const double want = whole.dz[k], got = dod.dz[k];
        ASSERT_TRUE(std::isnan(want) ? std::isnan(got) : want == got) << "sample " << k;
      }
    }
  }
}

TEST(TiledPartialTest, MergeRefusesMissingRepeatedAndForeignParts) {
  const Grid a = MakeGrid(40, 40, kGridA, {kX0 + 20, kY0 - 20, 0}, false, {}, 19u, "a.tif");
  const Grid b = MakeGrid(40, 40, kGridA, {kX0 + 20, kY0 - 20, 0}, true, {}, 20u, "b.tif");
  TiledMeasureOptions options;
  options.measure = Options();
  options.tile = 16;
  std::vector<TiledPartial> parts;
  for (int32_t k = 1; k <= 3; ++k) parts.push_back(MeasureTiledPart(a.Source(), b.Source(), options, k, 3));
  auto message = [](std::vector<TiledPartial> p) {
    try {
      MergeTiledPartials(std::move(p), nullptr);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message({parts[0], parts[2]}), "part 2/3 is missing");
  EXPECT_EQ(message({parts[0], parts[1], parts[1], parts[2]}), "part 2/3 is given twice");
  std::vector<TiledPartial> other = parts;
  other[1].tile = 32;
  EXPECT_NE(message(other).find("part 2/3 is of another run"), std::string::npos);
  EXPECT_EQ(message(parts), "");
}

}  // namespace
}  // namespace surfreg

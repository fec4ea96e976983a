#include "terrain/tiled_partial.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>

#include "measure/input_error.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<Point2> HullOfBoth(const std::vector<Point2>& a, const std::vector<Point2>& b) {
  std::vector<Point2> points = a;
  points.insert(points.end(), b.begin(), b.end());
  return ConvexHull(std::move(points));
}

[[noreturn]] void NoData(const std::string& source, const char* name) {
  throw InputError((source.empty() ? std::string(name) : source) +
                   ": no part of it is data (no raster cell has all four corners valid); "
                   "'domain: hull' measures over the convex hull instead");
}

std::string PartName(const TiledPartial& p) {
  return "part " + std::to_string(p.shard) + "/" + std::to_string(p.shards);
}

int64_t Key(int32_t column, int32_t row) { return (static_cast<int64_t>(row) << 32) | static_cast<uint32_t>(column); }

}  // namespace

void TiledSums::AddNode(double dz, double weight) {
  gap_sum += weight * std::fabs(dz);
  node_weight += weight;
  ++sum.n_overlap_nodes;
}

void TiledSums::AddTile(const MeasureSummary& s) {
  sum.rho_d += s.rho_d;
  sum.overlap_area += s.overlap_area;
  sum.weight_integral += s.weight_integral;
  sum.signed_volume += s.signed_volume;
  sum.volume_above += s.volume_above;
  sum.volume_below += s.volume_below;
  sum.fill_detected += s.fill_detected;
  sum.cut_detected += s.cut_detected;
  sum.fill_area += s.fill_area;
  sum.cut_area += s.cut_area;
  sum.n_cells += s.n_cells;
  sum.walk_steps += s.walk_steps;
  MeasureTimings& t = sum.timings;
  t.triangulate += s.timings.triangulate, t.domain += s.timings.domain;
  t.spanning_tree += s.timings.spanning_tree, t.locate += s.timings.locate;
  t.interpolate += s.timings.interpolate, t.volume += s.timings.volume;
}

void TiledSums::Add(const TiledSums& o) {
  AddTile(o.sum);
  sum.n_points_a += o.sum.n_points_a;
  sum.n_points_b += o.sum.n_points_b;
  sum.n_overlap_nodes += o.sum.n_overlap_nodes;
  gap_sum += o.gap_sum;
  node_weight += o.node_weight;
  domain_area_a += o.domain_area_a;
  domain_area_b += o.domain_area_b;
  complete_cells_a += o.complete_cells_a;
  complete_cells_b += o.complete_cells_b;
  hull_a = HullOfBoth(hull_a, o.hull_a);
  hull_b = HullOfBoth(hull_b, o.hull_b);
  budget.Add(o.budget);
}

void TiledBand(int64_t rows, int32_t shard, int32_t shards, int64_t* first, int64_t* end) {
  *first = rows * (shard - 1) / shards;
  *end = rows * shard / shards;
}

namespace {

// The parts (sorted by shard) are parts 1..n of one run, each finished.
void CheckPartsOfOneRun(const std::vector<TiledPartial>& parts) {
  const TiledPartial& first = parts.front();
  const int32_t n = first.shards;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const TiledPartial& p = parts[k];
    if (p.shards != n || p.tile != first.tile || p.tile_rows != first.tile_rows ||
        p.moving_tile_rows != first.moving_tile_rows) {
      throw InputError(PartName(p) + " is of another run than " + PartName(first) +
                       " (other shard count, tile or raster size)");
    }
    if (p.budget != first.budget || p.budget_sigma_dod != first.budget_sigma_dod ||
        p.budget_threshold != first.budget_threshold) {
      throw InputError(PartName(p) + " is of another run than " + PartName(first) +
                       " (another change budget: sigma or its threshold)");
    }
    if (k > 0 && p.shard == parts[k - 1].shard) throw InputError(PartName(p) + " is given twice");
    if (p.shard != static_cast<int32_t>(k) + 1) {
      throw InputError("part " + std::to_string(k + 1) + "/" + std::to_string(n) + " is missing");
    }
    int64_t a = 0, b = 0, ma = 0, mb = 0;
    TiledBand(p.tile_rows, p.shard, n, &a, &b);
    TiledBand(p.moving_tile_rows, p.shard, n, &ma, &mb);
    if (p.first_row != a || p.band_end_row != b || p.moving_first_row != ma || p.moving_end_row != mb) {
      throw InputError(PartName(p) + ": its tile rows are not those of part " +
                       std::to_string(p.shard) + " of " + std::to_string(n));
    }
    if (!p.complete()) throw InputError(PartName(p) + " is unfinished (an interrupted run: resume it)");
  }
  if (static_cast<int32_t>(parts.size()) != n) {
    throw InputError("part " + std::to_string(parts.size() + 1) + "/" + std::to_string(n) + " is missing");
  }
}

}  // namespace

TiledPartial MergeTiledPartials(std::vector<TiledPartial> parts, std::vector<TiledDodPatch>* patches) {
  if (parts.empty()) throw InputError("merge: no parts");
  std::sort(parts.begin(), parts.end(),
            [](const TiledPartial& p, const TiledPartial& q) { return p.shard < q.shard; });
  CheckPartsOfOneRun(parts);
  const TiledPartial& first = parts.front();
  TiledPartial whole = first;
  whole.shard = whole.shards = 1;
  whole.first_row = whole.moving_first_row = 0;
  whole.end_row = whole.band_end_row = first.tile_rows;
  whole.moving_end_row = first.moving_tile_rows;
  whole.sums = TiledSums();
  whole.stats = TiledMeasureStats();
  whole.border.clear();
  whole.shared.clear();
  // The parts of the shared sample row the band above left (row-major keys).
  std::map<int64_t, const TiledBorderNode*> above;
  std::map<int64_t, TiledSharedNode> shared;
  for (const TiledPartial& p : parts) {
    whole.sums.Add(p.sums);
    whole.stats.tiles += p.stats.tiles;
    whole.stats.tiles_measured += p.stats.tiles_measured;
    whole.stats.shared_moving_nodes += p.stats.shared_moving_nodes;
    whole.stats.merged_moving_nodes += p.stats.merged_moving_nodes;
    for (const TiledSharedNode& s : p.shared) {
      const auto inserted = shared.emplace(Key(s.column, s.row), s);
      if (!inserted.second) {
        ++whole.stats.merged_moving_nodes;
        --whole.stats.shared_moving_nodes;
      }
    }
    if (p.first_row == p.band_end_row) continue;  // an empty band: nothing crosses it
    for (const TiledBorderNode& node : p.border) {
      if (!node.owned) continue;
      // As the uninterrupted run: the first finite dz (all finite ones are
      // equal: measures.cc interpolates canonically), the parts' areas added.
      double dz = node.dz, area = node.area;
      const auto it = above.find(Key(node.column, node.row));
      if (it != above.end()) {
        if (std::isfinite(it->second->dz)) dz = it->second->dz;
        area = it->second->area + area;
        above.erase(it);
      }
      if (std::isfinite(dz)) whole.sums.AddNode(dz, node.weight);
      if (p.budget) whole.sums.budget.AddNode(dz, area, p.budget_sigma_dod, p.budget_threshold);
      if (patches != nullptr) patches->push_back({node.column, node.row, std::isfinite(dz) ? dz : kNaN});
    }
    if (!above.empty()) {
      throw InputError(PartName(p) + ": the shared row of samples differs from the band above "
                       "(parts of another run?)");
    }
    for (const TiledBorderNode& node : p.border) {
      if (!node.owned) above.emplace(Key(node.column, node.row), &node);
    }
  }
  for (const auto& entry : shared) whole.sums.AddNode(entry.second.dz, entry.second.weight);
  if (patches != nullptr) {
    std::sort(patches->begin(), patches->end(), [](const TiledDodPatch& p, const TiledDodPatch& q) {
      return Key(p.column, p.row) < Key(q.column, q.row);
    });
  }
  return whole;
}

MeasureSummary FinishTiled(const TiledSums& totals, const MeasureOptions& options,
                           const std::string& name_a, const std::string& name_b) {
  MeasureSummary summary = totals.sum;
  if (totals.complete_cells_a == 0) NoData(name_a, "surface A");
  if (totals.complete_cells_b == 0) NoData(name_b, "surface B");
  const double smaller = std::min(totals.domain_area_a, totals.domain_area_b);
  const double overlap = summary.overlap_area;
  if (!(overlap > options.min_overlap_fraction * smaller) || summary.n_cells == 0) {
    char numbers[160];
    std::snprintf(numbers, sizeof numbers,
                  " (overlap area %.3g, %.3g%% of the smaller data domain; the minimum is %.3g%%)",
                  overlap, smaller > 0.0 ? 100.0 * overlap / smaller : 0.0,
                  100.0 * options.min_overlap_fraction);
    throw InputError((name_a.empty() ? std::string("surface A") : name_a) + " and " +
                     (name_b.empty() ? std::string("surface B") : name_b) +
                     (overlap > 0.0 ? " overlap only in a sliver" : " do not overlap") + numbers);
  }
  summary.volume_mode = VolumeMode::kOverlay;
  summary.domain_kind = DomainKind::kData;
  summary.rho_d_axial = totals.node_weight > 0.0 ? totals.gap_sum / totals.node_weight : 0.0;
  summary.rho_s = summary.rho_d > 0.0 ? 1.0 / summary.rho_d : 1.0;
  summary.mean_abs_dz =
      summary.weight_integral > 0.0 ? summary.rho_d / summary.weight_integral : 0.0;
  summary.hull_area_a = PolygonArea(totals.hull_a);
  summary.hull_area_b = PolygonArea(totals.hull_b);
  summary.domain_area_a = totals.domain_area_a;
  summary.domain_area_b = totals.domain_area_b;
  summary.excluded_area_a = summary.hull_area_a - summary.domain_area_a;
  summary.excluded_area_b = summary.hull_area_b - summary.domain_area_b;
  summary.level_of_detection = options.level_of_detection;
  return summary;
}

}  // namespace surfreg

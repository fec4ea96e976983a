#include "measure/raster_pair.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "measure/grid_cells.h"
#include "measure/grid_pair.h"
#include "measure/raster_side.h"
#include "measure/tasks.h"

namespace surfreg {

using namespace grid_cells;
using namespace raster_sides;

namespace {

// The one-grid sweep: B's cell (c, r) is A's (c + dc, r + dr). Per chunk
// of A's box rows, its nodes and then its cells (grid_pair.cc's order);
// false if a position both have differs.
bool SweepSameGrid(const Execution& execution, const Side& a, const Side& b, int64_t dc, int64_t dr,
                   double sign, double lod, std::vector<ChunkSums>* out,
                   std::vector<double>* dz_a) {
  // A's columns whose B column is inside B's raster.
  const int64_t c_begin = std::max(a.c_lo, dc),
                c_end = std::min(a.c_hi + 1, b.raster->columns + dc);
  const int64_t box_rows = a.BoxRows();
  std::vector<ChunkSums>& parts = *out;
  parts.assign(RowChunks(box_rows), ChunkSums());
  // No column of A with B's beside it: nothing in common (Measure's error,
  // or zeros for a tile).
  if (c_begin >= c_end) return true;
  std::vector<uint8_t> same_positions(parts.size(), 1);
  ForEachChunk(execution, box_rows, static_cast<int>(parts.size()),
               [&](int chunk, int64_t begin, int64_t end) {
                 ChunkSums& sums = parts[chunk];
                 // Rolling rows of completeness: A's rows r − 1 and r, B's likewise.
                 std::vector<uint8_t> a_above(a.raster->columns), a_here(a.raster->columns),
                     b_above(b.raster->columns), b_here(b.raster->columns);
                 a.CompleteRow(a.r_lo + begin - 1, a_above.data());
                 b.CompleteRow(a.r_lo + begin - 1 - dr, b_above.data());
                 for (int64_t r = a.r_lo + begin; r < a.r_lo + end; ++r) {
                   if (r > a.r_lo + begin) a_above.swap(a_here), b_above.swap(b_here);
                   a.CompleteRow(r, a_here.data());
                   const int64_t rb_row = r - dr;
                   b.CompleteRow(rb_row, b_here.data());
                   if (rb_row < 0 || rb_row >= b.raster->rows)
                     continue;  // no node or cell of B in this row
                   // Nodes: A's sample numbers run over the whole row.
                   const double* za = a.raster->z + r * a.raster->columns;
                   const double* zb = b.raster->z + rb_row * b.raster->columns;
                   int64_t k = a.row_start[r];
                   for (int64_t c = 0; c < c_begin; ++c) k += std::isfinite(za[c]);
                   for (int64_t c = c_begin; c < c_end; ++c) {
                     if (!std::isfinite(za[c])) continue;
                     const int64_t i = k++;
                     if (!std::isfinite(zb[c - dc])) continue;
                     const Point2 pa = a.Xy(c, r), pb = b.Xy(c - dc, rb_row);
                     if (!(pa.x == pb.x && pa.y == pb.y)) same_positions[chunk] = 0;
                     if (!DomainVertex(a_above.data(), a_here.data(), c, a.raster->columns) ||
                         !DomainVertex(b_above.data(), b_here.data(), c - dc, b.raster->columns)) {
                       continue;
                     }
                     const double d = b.Z(c - dc, rb_row) - a.Z(c, r);
                     if (dz_a != nullptr) (*dz_a)[i] = d;
                     sums.gap_sum += std::fabs(d);
                     sums.node_weight += 1.0;
                     ++sums.nodes;
                   }
                   if (r + 1 >= a.raster->rows || rb_row + 1 >= b.raster->rows) continue;
                   for (int64_t c = c_begin; c < c_end; ++c) {
                     if (!a_here[c] || !b_here[c - dc]) continue;
                     const int64_t cs[4] = {c, c + 1, c + 1, c}, rs[4] = {r, r, r + 1, r + 1};
                     Point2 p[4];
                     double d[4];
                     for (int q = 0; q < 4; ++q) {
                       p[q] = a.Xy(cs[q], rs[q]);
                       d[q] = b.Z(cs[q] - dc, rs[q] - dr) - a.Z(cs[q], rs[q]);
                     }
                     // The rule's two triangles (grid_mesh.h), counter-clockwise.
                     static constexpr int kTriangles[2][3] = {{0, 1, 2}, {0, 2, 3}};
                     for (const auto& t : kTriangles) {
                       const int k0 = t[0], k1 = sign > 0.0 ? t[1] : t[2],
                                 k2 = sign > 0.0 ? t[2] : t[1];
                       const Point2 corners[3] = {p[k0], p[k1], p[k2]};
                       const double gaps[3] = {d[k0], d[k1], d[k2]};
                       IntegrateTriangle(corners, gaps, lod, &sums.volume);
                       ++sums.volume.cells;
                     }
                   }
                 }
               });
  return std::all_of(same_positions.begin(), same_positions.end(),
                     [](uint8_t s) { return s != 0; });
}

}  // namespace

bool MeasureRasterPair(const RasterHeights& ra, const RasterHeights& rb,
                       const std::array<double, 3>& origin, const MeasureOptions& options,
                       MeasureSummary* out, bool all_node_outputs) {
  std::string error;
  if (!options.grid_shortcut || options.volume != VolumeMode::kOverlay ||
      options.domain.kind != DomainKind::kData || options.weight != WeightMode::kUniform ||
      !options.IsValid(&error)) {
    return false;
  }
  if (ra.z == nullptr || rb.z == nullptr || ra.columns <= 0 || ra.rows <= 0 || rb.columns <= 0 ||
      rb.rows <= 0) {
    return false;
  }
  // The same cell vectors, non-degenerate (as FitAffine asks).
  const auto& ga = ra.geotransform;
  const auto& gb = rb.geotransform;
  if (ga[1] != gb[1] || ga[2] != gb[2] || ga[4] != gb[4] || ga[5] != gb[5]) return false;
  const Point2 u{ga[1], ga[4]}, v{ga[2], ga[5]};
  const double cross = u.x * v.y - u.y * v.x;
  if (!(std::fabs(cross) > 1e-6 * std::hypot(u.x, u.y) * std::hypot(v.x, v.y)) ||
      !std::isfinite(cross))
    return false;
  for (const auto* g : {&ga, &gb}) {
    for (const double x : *g) {
      if (!std::isfinite(x)) return false;
    }
  }
  // B's cell (c, r) is A's (c + dc, r + dr).
  const double ex = gb[0] - ga[0], ey = gb[3] - ga[3];
  const double fc = (ex * v.y - ey * v.x) / cross, fr = (u.x * ey - u.y * ex) / cross;
  if (!(std::fabs(fc) < 1e9 && std::fabs(fr) < 1e9)) return false;
  // On one grid (a whole-cell offset), or offset by a fraction of a cell.
  const bool one_grid =
      std::fabs(fc - std::round(fc)) <= 1e-6 && std::fabs(fr - std::round(fr)) <= 1e-6;

  const auto start = std::chrono::steady_clock::now();
  if (options.on_progress) {
    options.on_progress({one_grid ? "volume (one grid)" : "volume (offset grids)", 0.0, 0.0,
                         static_cast<int64_t>(ra.columns * ra.rows + rb.columns * rb.rows)});
  }
  const Execution execution = ExecutionFor(options.threads);
  Side a, b;
  a.raster = &ra, b.raster = &rb;
  a.origin = b.origin = {origin[0], origin[1]};
  a.z_origin = b.z_origin = origin[2];
  // One raster after the other, each in row chunks (on every core, where
  // side by side would be two).
  if (!Scan(execution, &a) || !Scan(execution, &b)) return false;
  // Positions within kMaxCoordinate (ValidateSurface): the boxes' corners.
  for (const Side* s : {&a, &b}) {
    for (const int64_t c : {s->c_lo, s->c_hi}) {
      for (const int64_t r : {s->r_lo, s->r_hi}) {
        const Point2 p = s->Xy(c, r);
        if (!(std::fabs(p.x + origin[0]) <= kMaxCoordinate &&
              std::fabs(p.y + origin[1]) <= kMaxCoordinate)) {
          return false;
        }
      }
    }
  }
  GridPairResult result;
  int64_t complete_a = 0, complete_b = 0;
  std::vector<uint8_t> flags_a, flags_b;  // every cell's completeness, for the offset sweep
  result.domain_area_a = DomainArea(execution, a, &complete_a, one_grid ? nullptr : &flags_a);
  result.domain_area_b = DomainArea(execution, b, &complete_b, one_grid ? nullptr : &flags_b);
  if (complete_a == 0 || complete_b == 0) return false;  // Measure names the surface with no data

  const double lod = options.detect_change ? options.level_of_detection : -1.0;
  const bool keep = options.keep_node_gaps;
  const bool keep_b =
      keep && all_node_outputs && !one_grid;  // on one grid every node of B in Ω is A's
  if (keep) result.dz_a.assign(static_cast<std::size_t>(a.samples), std::nan(""));
  if (keep_b) result.dz_b.assign(static_cast<std::size_t>(b.samples), std::nan(""));
  std::vector<ChunkSums> parts;
  if (one_grid) {
    if (!SweepSameGrid(execution, a, b, std::llround(fc), std::llround(fr),
                       cross > 0.0 ? 1.0 : -1.0, lod, &parts, keep ? &result.dz_a : nullptr)) {
      return false;
    }
  } else if (!SweepOffset(execution, a, b, flags_a, flags_b, fc, fr, std::fabs(cross), lod, &parts,
                          keep ? &result.dz_a : nullptr, keep_b ? &result.dz_b : nullptr)) {
    return false;
  }

  const ChunkSums total = SumChunks(parts);
  VolumeResult& volume = result.volume;
  volume = total.volume;
  const double gap_sum = total.gap_sum, node_weight = total.node_weight;
  const int64_t nodes = total.nodes;
  // An empty or sliver overlap: Measure's own error.
  const double smaller = std::min(result.domain_area_a, result.domain_area_b);
  if (!options.allow_empty_overlap &&
      (!(volume.area > options.min_overlap_fraction * smaller) || volume.cells == 0)) {
    return false;
  }
  result.rho_d_axial = node_weight > 0.0 ? gap_sum / node_weight : 0.0;
  result.n_overlap_nodes = nodes;
  const double cell_area = std::fabs(cross);
  result.hull_area_a = HullAreaOf(a, cell_area);
  result.hull_area_b = HullAreaOf(b, cell_area);
  if (keep && all_node_outputs) result.node_area_a = NodeAreasOf(execution, a, result.dz_a);

  MeasureSummary summary;
  summary.volume_mode = options.volume;
  summary.n_points_a = a.samples;
  summary.n_points_b = b.samples;
  SetVolumeFields(
      result.volume,
      {result.hull_area_a, result.hull_area_b, result.domain_area_a, result.domain_area_b}, options,
      &summary);
  summary.rho_d_axial = result.rho_d_axial;
  summary.n_overlap_nodes = result.n_overlap_nodes;
  if (keep) {
    summary.dz_a = std::move(result.dz_a);
    summary.node_area_a = std::move(result.node_area_a);
    summary.dz_b = std::move(result.dz_b);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.timings.volume = summary.timings.total = seconds;
  *out = std::move(summary);
  return true;
}

}  // namespace surfreg

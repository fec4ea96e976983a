#include "measure/grid_pair.h"

#include <algorithm>
#include <cmath>

#include "measure/grid_cells.h"
#include "measure/tasks.h"
#include "measure/weights.h"

namespace surfreg {

using namespace grid_cells;

bool MeasureOnSameGrid(const Surface& a, const Surface& b, const MeasureOptions& options,
                       GridPairResult* out) {
  if (!options.grid_shortcut || !a.raster_grid() || !b.raster_grid() || options.volume != VolumeMode::kOverlay ||
      options.domain.kind != DomainKind::kData || options.weight == WeightMode::kPerPoint) {
    return false;
  }
  GridSide sa, sb;
  const Execution execution = ExecutionFor(options.threads);
  if (!IndexSides(a, b, execution, &sa, &sb)) return false;
  GridAffine grid;
  double tolerance = 0.0;
  if (!FitAffine(a, std::max(Magnitude(a, execution), Magnitude(b, execution)), &grid, &tolerance, execution)) {
    return false;
  }

  // B's cell (c, r) is A's (c + dc, r + dr): from B's first sample, then
  // every sample of B checked on A's lattice, and equal to A's where both are.
  const Point2 q = sb.Xy(0);
  const double cross = grid.u.x * grid.v.y - grid.u.y * grid.v.x;
  const double ex = q.x - grid.origin.x, ey = q.y - grid.origin.y;
  const double fc = (ex * grid.v.y - ey * grid.v.x) / cross, fr = (grid.u.x * ey - grid.u.y * ex) / cross;
  if (!(std::fabs(fc) < 1e15 && std::fabs(fr) < 1e15)) return false;
  if (std::fabs(fc - std::round(fc)) > 1e-6 || std::fabs(fr - std::round(fr)) > 1e-6) return false;
  const int64_t dc = grid.c0 + std::llround(fc) - b.raster_cell[0].column;
  const int64_t dr = grid.r0 + std::llround(fr) - b.raster_cell[0].row;
  for (std::size_t j = 0; j < b.size(); ++j) {
    const int64_t c = b.raster_cell[j].column + dc, r = b.raster_cell[j].row + dr;
    const Point2 p = sb.Xy(static_cast<int32_t>(j));
    if (!Near(grid.At(c, r), p, tolerance)) return false;
    const int32_t i = sa.index.At(c, r);
    if (i >= 0 && !(a.xy[i].x == p.x && a.xy[i].y == p.y)) return false;
  }

  const double sign = cross > 0.0 ? 1.0 : -1.0;
  sa.cell_area = sb.cell_area = std::fabs(cross);
  double area_a = 0.0, area_b = 0.0;
  if (!MarkBoth(&sa, &sb, sign, ExecutionFor(options.threads), &area_a, &area_b)) return false;
  GridPairResult& result = *out;
  result = GridPairResult();
  result.domain_area_a = area_a;
  result.domain_area_b = area_b;

  // μ as the general path makes it (uniform or a mask: no mesh needed);
  // B's nodes are all A's, so only A's are weighed.
  const Triangulation no_mesh;
  const std::vector<double> no_weight;
  const std::vector<Location> no_locations;
  const WeightField mu = MakeWeightField(options, a, a.xy, no_mesh, no_weight, a.xy, no_mesh,
                                         no_weight, no_locations, no_locations);
  const double lod = options.detect_change ? options.level_of_detection : -1.0;
  const bool keep = options.keep_node_gaps;
  const bool uniform = options.weight == WeightMode::kUniform;
  std::vector<uint8_t> omega(a.size(), 0);
  if (keep) result.dz_a.assign(a.size(), std::nan(""));

  // Ω's nodes and cells over rows [begin, end) of A's index. Index
  // coordinates: A's (c, r) is B's (c + shift_c, r + shift_r).
  const int64_t shift_c = sa.index.c0 - dc - sb.index.c0, shift_r = sa.index.r0 - dr - sb.index.r0;
  const int64_t columns_b = sb.index.columns;
  // A's columns whose B column is inside B's index.
  const int64_t c_begin = std::max<int64_t>(0, -shift_c);
  const int64_t c_end = std::min<int64_t>(sa.index.columns, columns_b - shift_c);
  const auto rows = [&](int64_t begin, int64_t end, ChunkSums* sums) {
    for (int64_t r = begin; r < end; ++r) {
      const int64_t rb = r + shift_r;
      const int32_t* a_here = sa.SampleRow(r);
      const int32_t* b_here = sb.SampleRow(rb);
      if (b_here == nullptr) continue;  // no node or cell of B in this row
      const uint8_t* a_above = sa.CompleteRow(r - 1);
      const uint8_t* a_flags = sa.CompleteRow(r);
      const uint8_t* b_above = sb.CompleteRow(rb - 1);
      const uint8_t* b_flags = sb.CompleteRow(rb);
      for (int64_t c = c_begin; c < c_end; ++c) {
        const int32_t i = a_here[c], j = b_here[c + shift_c];
        if (i < 0 || j < 0 || !sa.DomainVertex(a_above, a_flags, c) ||
            !sb.DomainVertex(b_above, b_flags, c + shift_c)) {
          continue;
        }
        omega[i] = 1;
        const double d = sb.Z(j) - a.z[i];
        if (keep) result.dz_a[i] = d;
        const double w = uniform ? 1.0 : mu.AtNodeA(i);
        sums->gap_sum += w * std::fabs(d);
        sums->node_weight += w;
        ++sums->nodes;
      }
      const int32_t* a_below = sa.SampleRow(r + 1);
      const int32_t* b_below = sb.SampleRow(rb + 1);
      if (a_below == nullptr || b_below == nullptr) continue;
      for (int64_t c = c_begin; c < c_end; ++c) {
        if (!a_flags[c] || !b_flags[c + shift_c]) continue;
        int32_t ka[4], kb[4];
        GridSide::Corners(a_here, a_below, c, ka);
        GridSide::Corners(b_here, b_below, c + shift_c, kb);
        Point2 p[4];
        double d[4];
        for (int k = 0; k < 4; ++k) p[k] = a.xy[ka[k]], d[k] = sb.Z(kb[k]) - a.z[ka[k]];
        // The rule's two triangles (grid_mesh.h), counter-clockwise.
        const int triangles[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (const auto& t : triangles) {
          const int k0 = t[0], k1 = sign > 0.0 ? t[1] : t[2], k2 = sign > 0.0 ? t[2] : t[1];
          const Point2 corners[3] = {p[k0], p[k1], p[k2]};
          if (uniform) {
            const double gaps[3] = {d[k0], d[k1], d[k2]};
            IntegrateTriangle(corners, gaps, lod, &sums->volume);
          } else {
            const Plane gap = PlaneThrough(p[k0], p[k1], p[k2], d[k0], d[k1], d[k2]);
            IntegrateConvex(corners, 3, gap, mu, Plane(), &sums->volume, lod);
          }
          ++sums->volume.cells;
        }
      }
    }
  };
  std::vector<ChunkSums> parts(RowChunks(sa.index.rows));
  ForEachChunk(ExecutionFor(options.threads), sa.index.rows, static_cast<int>(parts.size()),
               [&](int c, int64_t begin, int64_t end) { rows(begin, end, &parts[c]); });
  FinishResult(parts, sa, sb, omega, keep, ExecutionFor(options.threads), &result);
  return true;
}

}  // namespace surfreg

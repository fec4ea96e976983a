// Two rasters on lattices of the same cell vectors, offset by a fraction of
// a cell (grid_pair.h, MeasureOnOffsetGrids). In A's index space B's
// lattice lines sit at the same fractional offsets in every A cell, so the
// overlay cut one A cell into the same pieces as every other: the pattern
// of pieces is clipped once in index space (each piece with its A triangle,
// its B cell and triangle, and the barycentric weights of its corners), and
// each cell's integrals follow from its corners' heights. A node of one
// lies at the same place in a cell of the other (strictly inside one
// triangle: offsets on a lattice line are left to the general path).
#include <algorithm>
#include <array>
#include <cmath>

#include "measure/grid_cells.h"
#include "measure/grid_pair.h"
#include "measure/tasks.h"
#include "measure/volume.h"

namespace surfreg {

using namespace grid_cells;

bool MeasureOnOffsetGrids(const Surface& a, const Surface& b, const MeasureOptions& options,
                          GridPairResult* out) {
  if (!options.grid_shortcut || !a.raster_grid() || !b.raster_grid() || options.volume != VolumeMode::kOverlay ||
      options.domain.kind != DomainKind::kData || options.weight != WeightMode::kUniform) {
    return false;
  }
  GridSide sa, sb;
  const Execution execution = ExecutionFor(options.threads);
  if (!IndexSides(a, b, execution, &sa, &sb)) return false;
  const double magnitude = std::max(Magnitude(a, execution), Magnitude(b, execution));
  GridAffine ga, gb;
  double tolerance_a = 0, tolerance_b = 0;
  if (!FitAffine(a, magnitude, &ga, &tolerance_a, execution) || !FitAffine(b, magnitude, &gb, &tolerance_b, execution)) {
    return false;
  }
  // The same cell vectors: every sample of B on A's vectors from B's origin
  // (so a turn between the grids, however small, that moves a sample by
  // more than the tolerance over B's extent is the general path's).
  const double cell = std::min(std::hypot(ga.u.x, ga.u.y), std::hypot(ga.v.x, ga.v.y));
  if (!Near(ga.u, gb.u, 1e-9 * cell) || !Near(ga.v, gb.v, 1e-9 * cell)) return false;
  gb.u = ga.u, gb.v = ga.v;
  for (std::size_t j = 0; j < b.size(); ++j) {
    if (!Near(gb.At(b.raster_cell[j].column, b.raster_cell[j].row), b.xy[j], tolerance_b)) return false;
  }
  const double cross = ga.u.x * ga.v.y - ga.u.y * ga.v.x;
  // B's side-index origin in A's side-index coordinates: (ox, oy).
  const Point2 q{gb.origin.x + sb.shift.x - ga.origin.x, gb.origin.y + sb.shift.y - ga.origin.y};
  const double ox = static_cast<double>(ga.c0 - sa.index.c0) + (q.x * ga.v.y - q.y * ga.v.x) / cross -
                    static_cast<double>(gb.c0 - sb.index.c0);
  const double oy = static_cast<double>(ga.r0 - sa.index.r0) + (ga.u.x * q.y - ga.u.y * q.x) / cross -
                    static_cast<double>(gb.r0 - sb.index.r0);
  if (!(std::fabs(ox) < 1e9 && std::fabs(oy) < 1e9)) return false;
  // A cell (c, r) meets B cells (c + kx + 0..1, r + ky + 0..1); nodes fall
  // strictly inside triangles unless an offset puts them on a line of the
  // other lattice (a whole-cell offset is one grid: MeasureOnSameGrid's).
  const int64_t kx = static_cast<int64_t>(std::floor(-ox)), ky = static_cast<int64_t>(std::floor(-oy));
  const double fx = Fraction(-ox), fy = Fraction(-oy);
  constexpr double kMargin = 1e-6;
  const auto on_line = [](double f) { return f < kMargin || f > 1.0 - kMargin; };
  if (on_line(fx) || on_line(fy) || on_line(Fraction(fx - fy))) return false;
  const double sign = cross > 0.0 ? 1.0 : -1.0;
  sa.cell_area = sb.cell_area = std::fabs(cross);
  GridPairResult& result = *out;
  result = GridPairResult();
  if (!MarkBoth(&sa, &sb, sign, ExecutionFor(options.threads), &result.domain_area_a, &result.domain_area_b)) return false;

  const std::vector<Piece> pieces = PiecePattern(fx, fy);
  const double area_scale = std::fabs(cross);  // xy area of one index unit
  const double lod = options.detect_change ? options.level_of_detection : -1.0;
  const bool keep = options.keep_node_gaps;
  std::vector<uint8_t> omega_a(a.size(), 0);
  if (keep) result.dz_a.assign(a.size(), std::nan("")), result.dz_b.assign(b.size(), std::nan(""));
  // A's node at the corner (0, 0) of its cell lies in B's cell (c + kx,
  // r + ky) at (fx, fy); B's node in A's cell (c - kx - 1, r - ky - 1) at
  // (1 - fx, 1 - fy).
  const int node_in_b = fx > fy ? 0 : 1, node_in_a = fy > fx ? 0 : 1;
  const std::array<double, 3> w_in_b = RuleWeights(node_in_b, fx, fy), w_in_a = RuleWeights(node_in_a, 1 - fx, 1 - fy);

  // The four corners' samples of complete cell (c, r) of a side, or false.
  const auto corners = [](const GridSide& side, int64_t c, int64_t r, int32_t k[4]) {
    const uint8_t* flags = side.CompleteRow(r);
    if (flags == nullptr || c < 0 || c >= side.index.columns || !flags[c]) return false;
    GridSide::Corners(side.SampleRow(r), side.SampleRow(r + 1), c, k);
    return true;
  };
  // The surface's interpolant at the point of rule triangle h with weights w.
  const auto at = [](const GridSide& side, const int32_t k[4], int h, const std::array<double, 3>& w) {
    return w[0] * side.Z(k[kRule[h][0]]) + w[1] * side.Z(k[kRule[h][1]]) + w[2] * side.Z(k[kRule[h][2]]);
  };
  // Nodes of `from` in rows [begin, end) inside `to`'s domain.
  const auto nodes = [&](const GridSide& from, const GridSide& to, int64_t dc, int64_t dr, int h,
                         const std::array<double, 3>& w, double sign_of_gap, std::vector<uint8_t>* omega,
                         std::vector<double>* gaps, int64_t begin, int64_t end, ChunkSums* sums) {
    for (int64_t r = begin; r < end; ++r) {
      const int32_t* here = from.SampleRow(r);
      const uint8_t* above = from.CompleteRow(r - 1);
      const uint8_t* flags = from.CompleteRow(r);
      for (int64_t c = 0; c < from.index.columns; ++c) {
        const int32_t i = here[c];
        int32_t k[4];
        if (i < 0 || !from.DomainVertex(above, flags, c) || !corners(to, c + dc, r + dr, k)) continue;
        const double d = sign_of_gap * (at(to, k, h, w) - from.Z(i));
        if (omega != nullptr) (*omega)[i] = 1;
        if (gaps != nullptr) (*gaps)[i] = d;
        sums->gap_sum += std::fabs(d);
        sums->node_weight += 1.0;
        ++sums->nodes;
      }
    }
  };
  // The pieces of A's cells in rows [begin, end).
  const auto cells = [&](int64_t begin, int64_t end, VolumeResult* volume) {
    for (int64_t r = begin; r < end; ++r) {
      for (int64_t c = 0; c < sa.index.columns; ++c) {
        int32_t ka[4];
        if (!corners(sa, c, r, ka)) continue;
        // The heights of A's four corners and of the four B cells' corners.
        double za[4], zb[2][2][4];
        bool whole[2][2];
        for (int k = 0; k < 4; ++k) za[k] = sa.Z(ka[k]);
        for (int dr = 0; dr < 2; ++dr) {
          for (int dc = 0; dc < 2; ++dc) {
            int32_t kb[4];
            whole[dr][dc] = corners(sb, c + kx + dc, r + ky + dr, kb);
            for (int k = 0; k < 4 && whole[dr][dc]; ++k) zb[dr][dc][k] = sb.Z(kb[k]);
          }
        }
        IntegratePieces(pieces, za, zb, whole, area_scale, lod, volume);
      }
    }
  };
  // A's and B's nodes and A's cells by chunks of A's rows (B's rows cut
  // into as many chunks).
  const int chunks = RowChunks(sa.index.rows);
  std::vector<ChunkSums> parts(chunks), parts_b(chunks);
  ForEachChunk(ExecutionFor(options.threads), sa.index.rows, chunks, [&](int h, int64_t a0, int64_t a1) {
    const int64_t b0 = ChunkBegin(sb.index.rows, chunks, h), b1 = ChunkBegin(sb.index.rows, chunks, h + 1);
    nodes(sa, sb, kx, ky, node_in_b, w_in_b, 1.0, &omega_a, keep ? &result.dz_a : nullptr, a0, a1, &parts[h]);
    nodes(sb, sa, -kx - 1, -ky - 1, node_in_a, w_in_a, -1.0, nullptr, keep ? &result.dz_b : nullptr, b0, b1,
          &parts_b[h]);
    cells(a0, a1, &parts[h].volume);
  });
  for (int h = 0; h < chunks; ++h) {  // B's nodes after A's, as the general path sums them
    parts[h].gap_sum += parts_b[h].gap_sum;
    parts[h].node_weight += parts_b[h].node_weight;
    parts[h].nodes += parts_b[h].nodes;
  }
  FinishResult(parts, sa, sb, omega_a, keep, ExecutionFor(options.threads), &result);
  return true;
}

}  // namespace surfreg

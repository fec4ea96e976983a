// Two rasters on lattices of the same cell vectors offset by a fraction of
// a cell, from their heights alone (raster_pair.h): grid_sweep.cc's sweep
// (one pattern of overlay pieces repeated in every A cell; each node at the
// same place in a cell of the other) with cells addressed by row and column
// instead of a sample index.
#include <array>
#include <cmath>

#include "measure/raster_side.h"
#include "measure/volume.h"

namespace surfreg {
namespace raster_sides {

using namespace grid_cells;

bool SweepOffset(const Execution& execution, const Side& a, const Side& b,
                 const std::vector<uint8_t>& complete_a, const std::vector<uint8_t>& complete_b,
                 double fc, double fr, double cell_area, double lod, std::vector<ChunkSums>* parts,
                 std::vector<double>* dz_a, std::vector<double>* dz_b) {
  // A's point (c, r) is B's (c − fc, r − fr): A cell (c, r) meets B cells
  // (c + kx + 0..1, r + ky + 0..1), A's nodes fall at (fx, fy) in B's cell
  // (c + kx, r + ky), B's at (1 − fx, 1 − fy) in A's (c − kx − 1, r − ky − 1).
  const int64_t kx = static_cast<int64_t>(std::floor(-fc)),
                ky = static_cast<int64_t>(std::floor(-fr));
  const double fx = Fraction(-fc), fy = Fraction(-fr);
  constexpr double kMargin =
      1e-6;  // as grid_sweep.cc: nodes on the other's lines go to the general path
  const auto on_line = [](double f) { return f < kMargin || f > 1.0 - kMargin; };
  if (on_line(fx) || on_line(fy) || on_line(Fraction(fx - fy))) return false;
  const std::vector<Piece> pieces = PiecePattern(fx, fy);
  const int node_in_b = fx > fy ? 0 : 1, node_in_a = fy > fx ? 0 : 1;
  const std::array<double, 3> w_in_b = RuleWeights(node_in_b, fx, fy);
  const std::array<double, 3> w_in_a = RuleWeights(node_in_a, 1 - fx, 1 - fy);

  // The heights of complete cell (c, r)'s corners (0,0) (1,0) (1,1) (0,1), or false.
  const auto corners = [](const Side& side, const std::vector<uint8_t>& complete, int64_t c,
                          int64_t r, double z[4]) {
    const int64_t columns = side.raster->columns;
    if (c < 0 || r < 0 || c >= columns || r >= side.raster->rows || !complete[r * columns + c])
      return false;
    z[0] = side.Z(c, r), z[1] = side.Z(c + 1, r), z[2] = side.Z(c + 1, r + 1),
    z[3] = side.Z(c, r + 1);
    return true;
  };
  // Nodes of `from` in its box rows [begin, end) inside `to`'s domain.
  const auto nodes = [&](const Side& from, const std::vector<uint8_t>& from_complete,
                         const Side& to, const std::vector<uint8_t>& to_complete, int64_t dc,
                         int64_t dr, int h, const std::array<double, 3>& w, double sign_of_gap,
                         std::vector<double>* gaps, int64_t begin, int64_t end, ChunkSums* sums) {
    const int64_t columns = from.raster->columns;
    const std::vector<uint8_t> none(static_cast<std::size_t>(columns), 0);
    for (int64_t r = from.r_lo + begin; r < from.r_lo + end; ++r) {
      const double* z = from.raster->z + r * columns;
      const uint8_t* above = r >= 1 ? &from_complete[(r - 1) * columns] : none.data();
      const uint8_t* here = &from_complete[r * columns];
      int64_t k = from.row_start[r];
      for (int64_t c = 0; c < columns; ++c) {
        if (!std::isfinite(z[c])) continue;
        const int64_t i = k++;
        double zt[4];
        if (!DomainVertex(above, here, c, columns) || !corners(to, to_complete, c + dc, r + dr, zt))
          continue;
        const int* t = kRule[h];
        const double d =
            sign_of_gap * ((w[0] * zt[t[0]] + w[1] * zt[t[1]] + w[2] * zt[t[2]]) - from.Z(c, r));
        if (gaps != nullptr) (*gaps)[i] = d;
        sums->gap_sum += std::fabs(d);
        sums->node_weight += 1.0;
        ++sums->nodes;
      }
    }
  };
  // The pieces of A's cells in its box rows [begin, end).
  const auto cells = [&](int64_t begin, int64_t end, VolumeResult* volume) {
    for (int64_t r = a.r_lo + begin; r < a.r_lo + end; ++r) {
      for (int64_t c = a.c_lo; c <= a.c_hi; ++c) {
        double za[4], zb[2][2][4];
        if (!corners(a, complete_a, c, r, za)) continue;
        bool whole[2][2];
        for (int dr = 0; dr < 2; ++dr) {
          for (int dc = 0; dc < 2; ++dc)
            whole[dr][dc] = corners(b, complete_b, c + kx + dc, r + ky + dr, zb[dr][dc]);
        }
        IntegratePieces(pieces, za, zb, whole, cell_area, lod, volume);
      }
    }
  };
  // A's and B's nodes and A's cells by chunks of A's box rows (B's box rows
  // cut into as many chunks); B's nodes' sums after A's, as grid_sweep.cc.
  const int64_t rows_a = a.BoxRows(), rows_b = b.BoxRows();
  const int chunks = RowChunks(rows_a);
  parts->assign(chunks, ChunkSums());
  std::vector<ChunkSums> parts_b(chunks);
  ForEachChunk(execution, rows_a, chunks, [&](int h, int64_t a0, int64_t a1) {
    const int64_t b0 = ChunkBegin(rows_b, chunks, h), b1 = ChunkBegin(rows_b, chunks, h + 1);
    nodes(a, complete_a, b, complete_b, kx, ky, node_in_b, w_in_b, 1.0, dz_a, a0, a1, &(*parts)[h]);
    nodes(b, complete_b, a, complete_a, -kx - 1, -ky - 1, node_in_a, w_in_a, -1.0, dz_b, b0, b1,
          &parts_b[h]);
    cells(a0, a1, &(*parts)[h].volume);
  });
  for (int h = 0; h < chunks; ++h) {
    (*parts)[h].gap_sum += parts_b[h].gap_sum;
    (*parts)[h].node_weight += parts_b[h].node_weight;
    (*parts)[h].nodes += parts_b[h].nodes;
  }
  return true;
}

}  // namespace raster_sides
}  // namespace surfreg

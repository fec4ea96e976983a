#include "measure/grid_mesh.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "measure/enforce_triangles.h"
#include "measure/input_error.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

bool RowMajorLess(const RasterCell& a, const RasterCell& b) {
  return a.row != b.row ? a.row < b.row : a.column < b.column;
}

std::array<int32_t, 3> Sorted(const int32_t* v) {
  std::array<int32_t, 3> s = {v[0], v[1], v[2]};
  std::sort(s.begin(), s.end());
  return s;
}

}  // namespace

std::vector<int32_t> GridCellTriangles(const std::vector<RasterCell>& cells, const std::string& source,
                                       const Execution& execution) {
  const std::size_t n = cells.size();
  // Row-major order of the samples: the reader's own order needs no sort.
  std::vector<int32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<int32_t>(i);
  bool sorted = true;
  for (std::size_t i = 1; i < n && sorted; ++i) sorted = RowMajorLess(cells[i - 1], cells[i]);
  if (!sorted) {
    std::sort(order.begin(), order.end(),
              [&](int32_t a, int32_t b) { return RowMajorLess(cells[a], cells[b]); });
  }
  for (std::size_t i = 1; i < n; ++i) {
    const RasterCell& a = cells[order[i - 1]];
    const RasterCell& b = cells[order[i]];
    if (a.row == b.row && a.column == b.column) {
      throw InputError((source.empty() ? std::string("surface") : source) +
                       ": two samples have raster cell (" + std::to_string(a.column) + ", " +
                       std::to_string(a.row) + ")");
    }
  }
  auto column = [&](std::size_t k) { return static_cast<int64_t>(cells[order[k]].column); };
  auto row = [&](std::size_t k) { return static_cast<int64_t>(cells[order[k]].row); };
  // The complete cells whose lower row starts in [begin, stop) (a row's
  // first sample), in order: one row at a time, with a pointer into the
  // next row that only moves on.
  const auto each_cell = [&](std::size_t begin, std::size_t stop, auto&& emit) {
    while (begin < stop) {
      std::size_t end = begin;
      while (end < n && row(end) == row(begin)) ++end;
      std::size_t next_end = end;
      while (next_end < n && row(next_end) == row(begin) + 1) ++next_end;
      std::size_t j = end;
      for (std::size_t i = begin; end < next_end && i + 1 < end; ++i) {
        if (column(i + 1) != column(i) + 1) continue;
        while (j < next_end && column(j) < column(i)) ++j;
        if (!(j + 1 < next_end && column(j) == column(i) && column(j + 1) == column(i) + 1)) continue;
        emit(order[i], order[i + 1], order[j], order[j + 1]);
      }
      begin = end;
    }
  };
  // Chunks of samples moved on to a row's start (their number a function of
  // the size only); the cells counted, then written at their offsets.
  const int chunks = ChunksFor(static_cast<int64_t>(n), int64_t{1} << 16);
  std::vector<std::size_t> first(static_cast<std::size_t>(chunks) + 1, n);
  first[0] = 0;
  for (int c = 1; c < chunks; ++c) {
    std::size_t k = std::max(first[c - 1], static_cast<std::size_t>(ChunkBegin(static_cast<int64_t>(n), chunks, c)));
    while (k > 0 && k < n && row(k) == row(k - 1)) ++k;
    first[c] = k;
  }
  std::vector<std::size_t> offset(static_cast<std::size_t>(chunks) + 1, 0);
  ForEachChunk(execution, chunks, chunks, [&](int c, int64_t, int64_t) {
    std::size_t count = 0;
    each_cell(first[c], first[c + 1], [&](int32_t, int32_t, int32_t, int32_t) { ++count; });
    offset[c + 1] = 6 * count;
  });
  for (int c = 0; c < chunks; ++c) offset[c + 1] += offset[c];
  std::vector<int32_t> triangles(offset[chunks]);
  ForEachChunk(execution, chunks, chunks, [&](int c, int64_t, int64_t) {
    int32_t* out = triangles.data() + offset[c];
    each_cell(first[c], first[c + 1], [&](int32_t p00, int32_t p10, int32_t p01, int32_t p11) {
      const int32_t cell[6] = {p00, p10, p11, p00, p11, p01};
      out = std::copy(cell, cell + 6, out);
    });
  });
  return triangles;
}

void RemapGridTriangles(const std::vector<int32_t>& new_index, std::vector<int32_t>* triangles) {
  std::vector<int32_t>& t = *triangles;
  std::size_t kept = 0;
  for (std::size_t c = 0; c + 6 <= t.size(); c += 6) {
    int32_t v[6];
    bool whole = true;
    for (int k = 0; k < 6; ++k) {
      v[k] = new_index[t[c + k]];
      whole = whole && v[k] >= 0;
    }
    if (!whole) continue;
    std::copy(v, v + 6, t.begin() + kept);
    kept += 6;
  }
  t.resize(kept);
}

namespace {

// The cells' triangles to enforce, counter-clockwise: all cells but the
// folded ones (a triangle against the orientation most grid triangles have;
// a mirrored or upside-down grid has the other; a merged duplicate corner
// makes its cell degenerate) and every cell sharing a corner with one.
std::vector<int32_t> UnfoldedCellTriangles(const std::vector<Point2>& xy, const std::vector<int32_t>& cell_triangles,
                                           const Triangulation& mesh, int64_t* folded) {
  const std::size_t num_cells = cell_triangles.size() / 6;
  std::vector<int8_t> sign(2 * num_cells, 0);
  int64_t positive = 0, negative = 0;
  for (std::size_t k = 0; k < 2 * num_cells; ++k) {
    const int32_t* v = &cell_triangles[3 * k];
    bool own = true;
    for (int i = 0; i < 3; ++i) own = own && mesh.vertex_of_input[v[i]] == v[i];
    const double o = own ? Orient2D(xy[v[0]], xy[v[1]], xy[v[2]]) : 0.0;
    sign[k] = o > 0.0 ? 1 : o < 0.0 ? -1 : 0;
    positive += sign[k] > 0;
    negative += sign[k] < 0;
  }
  const int8_t want = negative > positive ? -1 : 1;
  std::vector<uint8_t> near_fold(xy.size(), 0);
  *folded = 0;
  for (std::size_t c = 0; c < num_cells; ++c) {
    if (sign[2 * c] == want && sign[2 * c + 1] == want) continue;
    ++*folded;
    for (int k = 0; k < 6; ++k) near_fold[cell_triangles[6 * c + k]] = 1;
  }
  std::vector<int32_t> required;
  required.reserve(cell_triangles.size());
  for (std::size_t c = 0; c < num_cells; ++c) {
    const int32_t* v = &cell_triangles[6 * c];
    bool clear = true;
    for (int k = 0; k < 6; ++k) clear = clear && !near_fold[v[k]];
    if (!clear) continue;
    for (int t = 0; t < 2; ++t) {
      const int32_t* w = v + 3 * t;
      if (want > 0) {
        required.insert(required.end(), {w[0], w[1], w[2]});
      } else {
        required.insert(required.end(), {w[0], w[2], w[1]});
      }
    }
  }
  return required;
}

// Per required triangle, the mesh triangle with its corners (−1 if it is
// not a face: enforcement failed there), by indexing the required ones by
// their smallest vertex.
std::vector<int32_t> FacesOf(const std::vector<int32_t>& required, std::size_t num_vertices,
                             const Triangulation& mesh) {
  const std::size_t num_required = required.size() / 3;
  std::vector<int32_t> begin(num_vertices + 1, 0);
  for (std::size_t r = 0; r < num_required; ++r) ++begin[Sorted(&required[3 * r])[0] + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) begin[v + 1] += begin[v];
  std::vector<int32_t> by_vertex(num_required);
  std::vector<int32_t> fill(begin.begin(), begin.end() - 1);
  for (std::size_t r = 0; r < num_required; ++r) {
    by_vertex[fill[Sorted(&required[3 * r])[0]]++] = static_cast<int32_t>(r);
  }
  std::vector<int32_t> face(num_required, -1);
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const std::array<int32_t, 3> s = Sorted(&mesh.triangles[3 * t]);
    for (int32_t k = begin[s[0]]; k < begin[s[0] + 1]; ++k) {
      const int32_t r = by_vertex[k];
      if (Sorted(&required[3 * r]) == s) face[r] = t;
    }
  }
  return face;
}

}  // namespace

std::vector<uint8_t> EnforceGrid(const std::vector<Point2>& xy,
                                 const std::vector<int32_t>& cell_triangles, Triangulation* mesh,
                                 GridMeshStats* stats) {
  if (cell_triangles.size() % 6 != 0) {
    throw std::invalid_argument("EnforceGrid: cell_triangles.size() is not a multiple of 6");
  }
  const std::size_t num_cells = cell_triangles.size() / 6;
  int64_t folded = 0;
  const std::vector<int32_t> required = UnfoldedCellTriangles(xy, cell_triangles, *mesh, &folded);
  EnforceTriangles(xy, required, mesh);
  // Which kept cells are faces now (all of them unless enforcement failed).
  const std::vector<int32_t> face = FacesOf(required, xy.size(), *mesh);
  std::vector<uint8_t> in_grid(mesh->num_triangles(), 0);
  int64_t kept = 0;
  for (std::size_t c = 0; 2 * c + 1 < face.size(); ++c) {
    const int32_t t0 = face[2 * c], t1 = face[2 * c + 1];
    if (t0 < 0 || t1 < 0) continue;
    in_grid[t0] = in_grid[t1] = 1;
    ++kept;
  }
  if (stats != nullptr) {
    stats->cells = static_cast<int64_t>(num_cells);
    stats->folded_cells = folded;
    stats->dropped_cells = static_cast<int64_t>(num_cells) - kept;
  }
  return in_grid;
}

}  // namespace surfreg

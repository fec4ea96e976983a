#include "measure/raster_side.h"

#include <algorithm>

#include "measure/predicates.h"

namespace surfreg {
namespace raster_sides {

using namespace grid_cells;

bool Scan(const Execution& execution, Side* side) {
  const RasterHeights& raster = *side->raster;
  const int64_t rows = raster.rows, columns = raster.columns;
  std::vector<int64_t> count(static_cast<std::size_t>(rows), 0);
  side->row_ends.assign(static_cast<std::size_t>(rows), {-1, -1});
  const int chunks = RowChunks(rows);
  std::vector<uint8_t> in_range(chunks, 1);
  ForEachChunk(execution, rows, chunks, [&](int chunk, int64_t begin, int64_t end) {
    for (int64_t r = begin; r < end; ++r) {
      const double* row = raster.z + r * columns;
      int64_t n = 0, first = -1, last = -1;
      for (int64_t c = 0; c < columns; ++c) {
        if (!std::isfinite(row[c])) continue;
        if (!(std::fabs(row[c]) <= kMaxCoordinate)) in_range[chunk] = 0;
        if (first < 0) first = c;
        last = c;
        ++n;
      }
      count[r] = n;
      side->row_ends[r] = {first, last};
    }
  });
  if (!std::all_of(in_range.begin(), in_range.end(), [](uint8_t v) { return v != 0; }))
    return false;
  side->row_start.assign(static_cast<std::size_t>(rows) + 1, 0);
  for (int64_t r = 0; r < rows; ++r) {
    side->row_start[r + 1] = side->row_start[r] + count[r];
    const auto& e = side->row_ends[r];
    if (e[0] < 0) continue;
    if (side->c_hi < side->c_lo) {
      side->c_lo = e[0], side->c_hi = e[1], side->r_lo = r;
    }
    side->c_lo = std::min(side->c_lo, e[0]), side->c_hi = std::max(side->c_hi, e[1]);
    side->r_hi = r;
  }
  side->samples = side->row_start[rows];
  return side->samples > 0;
}

double DomainArea(const Execution& execution, const Side& side, int64_t* complete_cells,
                  std::vector<uint8_t>* complete_out) {
  const int64_t rows = side.BoxRows();
  const int chunks = RowChunks(rows);
  std::vector<double> area(chunks, 0.0);
  std::vector<int64_t> cells(chunks, 0);
  // North-up (no rotation terms): x depends on the column only and y on
  // the row only, so both triangles' TwiceArea is exactly dx · dy (the
  // other product is a zero); the same doubles without the positions.
  const auto& g = side.raster->geotransform;
  const bool north_up = g[2] == 0.0 && g[4] == 0.0;
  std::vector<double> dx;
  if (north_up) {
    dx.resize(static_cast<std::size_t>(side.raster->columns), 0.0);
    for (int64_t c = side.c_lo; c < side.c_hi; ++c) dx[c] = side.Xy(c + 1, 0).x - side.Xy(c, 0).x;
  }
  const int64_t columns = side.raster->columns;
  if (complete_out != nullptr)
    complete_out->assign(static_cast<std::size_t>(columns * side.raster->rows), 0);
  ForEachChunk(execution, rows, chunks, [&](int chunk, int64_t begin, int64_t end) {
    double twice = 0.0;
    std::vector<uint8_t> row_flags(complete_out != nullptr ? 0 : static_cast<std::size_t>(columns));
    for (int64_t r = side.r_lo + begin; r < side.r_lo + end && r < side.r_hi; ++r) {
      uint8_t* complete =
          complete_out != nullptr ? complete_out->data() + r * columns : row_flags.data();
      side.CompleteRow(r, complete);
      const double dy = side.Xy(0, r + 1).y - side.Xy(0, r).y;
      for (int64_t c = side.c_lo; c < side.c_hi; ++c) {
        if (!complete[c]) continue;
        ++cells[chunk];
        if (north_up) {
          const double t = std::fabs(dx[c] * dy);
          twice += t + t;
          continue;
        }
        const Point2 p[4] = {side.Xy(c, r), side.Xy(c + 1, r), side.Xy(c + 1, r + 1),
                             side.Xy(c, r + 1)};
        twice += std::fabs(TwiceArea(p[0], p[1], p[2])) + std::fabs(TwiceArea(p[0], p[2], p[3]));
      }
    }
    area[chunk] = 0.5 * twice;
  });
  double total = 0.0;
  *complete_cells = 0;
  for (int c = 0; c < chunks; ++c) total += area[c], *complete_cells += cells[c];
  return total;
}

double HullAreaOf(const Side& side, double cell_area) {
  std::vector<std::array<int64_t, 2>> ends;
  for (int64_t r = side.r_lo; r <= side.r_hi; ++r) {
    const auto& e = side.row_ends[r];
    if (e[0] < 0) continue;
    ends.push_back({e[0], r});
    if (e[1] != e[0]) ends.push_back({e[1], r});
  }
  return HullAreaOfRowEnds(std::move(ends), cell_area);
}

std::vector<double> NodeAreasOf(const Execution& execution, const Side& a,
                                const std::vector<double>& dz_a) {
  std::vector<double> node_area(static_cast<std::size_t>(a.samples), 0.0);
  const int64_t rows = a.BoxRows();
  // Sample numbers of a row's valid cells (−1 elsewhere), per row as needed.
  const auto number_row = [&](int64_t r, int64_t* out) {
    const int64_t columns = a.raster->columns;
    std::fill(out, out + columns, -1);
    if (r < 0 || r >= a.raster->rows) return;
    int64_t k = a.row_start[r];
    for (int64_t c = 0; c < columns; ++c) {
      if (a.Valid(c, r)) out[c] = k++;
    }
  };
  ForEachChunk(execution, rows, RowChunks(rows), [&](int, int64_t begin, int64_t end) {
    const int64_t columns = a.raster->columns;
    // Rolling rows: sample numbers of rows r − 1, r, r + 1 and the thirds of
    // the cells of rows r − 1 and r (two per cell, 0 outside Ω's triangles).
    std::vector<int64_t> up(columns), here(columns), down(columns);
    std::vector<double> thirds_up(2 * columns), thirds_here(2 * columns);
    const auto thirds_of_row = [&](int64_t r, const int64_t* top, const int64_t* bottom,
                                   double* out) {
      std::fill(out, out + 2 * columns, 0.0);
      if (r < a.r_lo || r >= a.r_hi) return;
      for (int64_t c = a.c_lo; c < a.c_hi; ++c) {
        const int64_t k[4] = {top[c], top[c + 1], bottom[c + 1], bottom[c]};
        if (k[0] < 0 || k[1] < 0 || k[2] < 0 || k[3] < 0) continue;
        const Point2 p[4] = {a.Xy(c, r), a.Xy(c + 1, r), a.Xy(c + 1, r + 1), a.Xy(c, r + 1)};
        static constexpr int kTriangles[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int j = 0; j < 2; ++j) {
          const int* t = kTriangles[j];
          if (!std::isfinite(dz_a[k[t[0]]]) || !std::isfinite(dz_a[k[t[1]]]) ||
              !std::isfinite(dz_a[k[t[2]]])) {
            continue;
          }
          out[2 * c + j] = std::fabs(Orient2D(p[t[0]], p[t[1]], p[t[2]])) / 6.0;
        }
      }
    };
    const int64_t r_begin = a.r_lo + begin;
    number_row(r_begin - 1, up.data());
    number_row(r_begin, here.data());
    number_row(r_begin + 1, down.data());
    thirds_of_row(r_begin - 1, up.data(), here.data(), thirds_up.data());
    for (int64_t r = r_begin; r < a.r_lo + end; ++r) {
      thirds_of_row(r, here.data(), down.data(), thirds_here.data());
      for (int64_t c = 0; c < columns; ++c) {
        if (here[c] < 0) continue;
        // The cells (c − 1, r − 1), (c, r − 1), (c − 1, r), (c, r) and the
        // triangles of each that have this corner (NodeAreas' order).
        double sum = 0.0;
        if (c >= 1) sum += thirds_up[2 * (c - 1)], sum += thirds_up[2 * (c - 1) + 1];
        if (c + 1 < columns) sum += thirds_up[2 * c + 1];
        if (c >= 1) sum += thirds_here[2 * (c - 1)];
        if (c + 1 < columns) sum += thirds_here[2 * c], sum += thirds_here[2 * c + 1];
        node_area[here[c]] = sum;
      }
      up.swap(here);
      here.swap(down);
      number_row(r + 2, down.data());
      thirds_up.swap(thirds_here);
    }
  });
  return node_area;
}

}  // namespace raster_sides
}  // namespace surfreg

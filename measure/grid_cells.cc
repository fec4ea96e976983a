#include "measure/grid_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "measure/predicates.h"
#include "measure/tasks.h"
#include "measure/volume.h"

namespace surfreg {
namespace grid_cells {

namespace {

// A box this much larger than the samples would cost more memory than the
// general path saves: a sparse raster is left to it.
constexpr int64_t kMaxBoxPerSample = 16;

}  // namespace

bool BuildIndex(const std::vector<RasterCell>& cells, GridIndex* index, const Execution& execution) {
  if (cells.empty()) return false;
  // The box, and whether the cells run in strictly increasing row-major
  // order (as the raster reader makes them: then no two share a cell), by
  // chunks.
  const int64_t n = static_cast<int64_t>(cells.size());
  const int chunks = ChunksFor(n, int64_t{1} << 16);
  struct Box {
    int64_t c_lo, c_hi, r_lo, r_hi;
    bool ordered;
  };
  const auto before = [](const RasterCell& p, const RasterCell& q) {
    return p.row < q.row || (p.row == q.row && p.column < q.column);
  };
  std::vector<Box> parts(static_cast<std::size_t>(chunks));
  ForEachChunk(execution, n, chunks, [&](int h, int64_t first, int64_t last) {
    Box box{cells[first].column, cells[first].column, cells[first].row, cells[first].row,
            first == 0 || before(cells[first - 1], cells[first])};
    for (int64_t i = first; i < last; ++i) {
      const RasterCell& cell = cells[i];
      box.c_lo = std::min<int64_t>(box.c_lo, cell.column), box.c_hi = std::max<int64_t>(box.c_hi, cell.column);
      box.r_lo = std::min<int64_t>(box.r_lo, cell.row), box.r_hi = std::max<int64_t>(box.r_hi, cell.row);
      if (i > first && !before(cells[i - 1], cell)) box.ordered = false;
    }
    parts[h] = box;
  });
  Box box = parts[0];
  for (const Box& part : parts) {
    box.c_lo = std::min(box.c_lo, part.c_lo), box.c_hi = std::max(box.c_hi, part.c_hi);
    box.r_lo = std::min(box.r_lo, part.r_lo), box.r_hi = std::max(box.r_hi, part.r_hi);
    box.ordered = box.ordered && part.ordered;
  }
  index->c0 = box.c_lo, index->r0 = box.r_lo;
  index->columns = box.c_hi - box.c_lo + 1, index->rows = box.r_hi - box.r_lo + 1;
  const int64_t most = kMaxBoxPerSample * n + 4096;
  if (index->columns > most || index->rows > most || index->rows > most / index->columns) {
    return false;
  }
  AssignInChunks(execution, static_cast<std::size_t>(index->rows * index->columns), int32_t{-1}, &index->sample);
  const auto slot_of = [&](const RasterCell& cell) {
    return static_cast<std::size_t>((cell.row - index->r0) * index->columns + (cell.column - index->c0));
  };
  if (box.ordered) {  // every cell its own slot
    ForEachChunk(execution, n, chunks, [&](int, int64_t first, int64_t last) {
      for (int64_t i = first; i < last; ++i) index->sample[slot_of(cells[i])] = static_cast<int32_t>(i);
    });
    return true;
  }
  for (std::size_t i = 0; i < cells.size(); ++i) {
    int32_t& slot = index->sample[slot_of(cells[i])];
    if (slot >= 0) return false;
    slot = static_cast<int32_t>(i);
  }
  return true;
}

std::vector<Point2> HullCandidates(const Surface& s, const GridIndex& index, const Execution& execution) {
  const auto at = [&](int64_t c, int64_t r) {  // index coordinates; -1 outside
    if (c < 0 || r < 0 || c >= index.columns || r >= index.rows) return -1;
    return index.sample[static_cast<std::size_t>(r * index.columns + c)];
  };
  // By chunks of rows, summed in chunk order: the same on any thread count.
  const int chunks = RowChunks(index.rows);
  struct Sums {
    Point2 u{0, 0}, v{0, 0}, mean{0, 0};
    double nu = 0, nv = 0, mc = 0, mr = 0, n = 0, e2 = 0;
  };
  std::vector<Sums> parts(chunks);
  // L: the mean step to the next column and row, through the samples' mean.
  ForEachChunk(execution, index.rows, chunks, [&](int h, int64_t begin, int64_t end) {
    Sums p;
    for (int64_t r = begin; r < end; ++r) {
      for (int64_t c = 0; c < index.columns; ++c) {
        const int32_t i = at(c, r);
        if (i < 0) continue;
        p.mean.x += s.xy[i].x, p.mean.y += s.xy[i].y, ++p.n;
        p.mc += static_cast<double>(c), p.mr += static_cast<double>(r);
        const int32_t right = at(c + 1, r), down = at(c, r + 1);
        if (right >= 0) p.u.x += s.xy[right].x - s.xy[i].x, p.u.y += s.xy[right].y - s.xy[i].y, ++p.nu;
        if (down >= 0) p.v.x += s.xy[down].x - s.xy[i].x, p.v.y += s.xy[down].y - s.xy[i].y, ++p.nv;
      }
    }
    parts[h] = p;
  });
  Sums t;
  for (const Sums& p : parts) {
    t.u.x += p.u.x, t.u.y += p.u.y, t.v.x += p.v.x, t.v.y += p.v.y, t.mean.x += p.mean.x, t.mean.y += p.mean.y;
    t.nu += p.nu, t.nv += p.nv, t.mc += p.mc, t.mr += p.mr, t.n += p.n;
  }
  bool rim_only = t.nu > 0 && t.nv > 0 && t.n > 0;
  if (rim_only) {
    const Point2 u{t.u.x / t.nu, t.u.y / t.nu}, v{t.v.x / t.nv, t.v.y / t.nv};
    const Point2 mean{t.mean.x / t.n, t.mean.y / t.n};
    const double mc = t.mc / t.n, mr = t.mr / t.n;
    const double cross = std::fabs(u.x * v.y - u.y * v.x);
    const double inradius = std::min(cross / std::hypot(u.x, u.y), cross / std::hypot(v.x, v.y));
    // The largest squared distance from L.
    ForEachChunk(execution, index.rows, chunks, [&](int h, int64_t begin, int64_t end) {
      double e2 = 0;
      for (int64_t r = begin; r < end; ++r) {
        for (int64_t c = 0; c < index.columns; ++c) {
          const int32_t i = at(c, r);
          if (i < 0) continue;
          const double dc = static_cast<double>(c) - mc, dr = static_cast<double>(r) - mr;
          const double ex = s.xy[i].x - (mean.x + dc * u.x + dr * v.x);
          const double ey = s.xy[i].y - (mean.y + dc * u.y + dr * v.y);
          e2 = std::max(e2, ex * ex + ey * ey);
        }
      }
      parts[h].e2 = e2;
    });
    double e2 = 0;
    for (const Sums& p : parts) e2 = std::max(e2, p.e2);
    // The sample off L by E and its neighbours' hull shrunk by E at most:
    // inside while 2E is below the block's inradius (a quarter: margin).
    rim_only = std::isfinite(e2) && 2.0 * std::sqrt(e2) < 0.25 * inradius;
  }
  if (!rim_only) return s.xy;
  std::vector<std::vector<Point2>> rims(chunks);
  ForEachChunk(execution, index.rows, chunks, [&](int h, int64_t begin, int64_t end) {
    for (int64_t r = begin; r < end; ++r) {
      for (int64_t c = 0; c < index.columns; ++c) {
        const int32_t i = at(c, r);
        if (i < 0) continue;
        bool inner = true;
        for (int dr = -1; dr <= 1 && inner; ++dr) {
          for (int dc = -1; dc <= 1 && inner; ++dc) inner = at(c + dc, r + dr) >= 0;
        }
        if (!inner) rims[h].push_back(s.xy[i]);
      }
    }
  });
  std::vector<Point2> rim;
  for (const std::vector<Point2>& part : rims) rim.insert(rim.end(), part.begin(), part.end());
  return rim;
}

bool Near(const Point2& p, const Point2& q, double tolerance) {
  return std::fabs(p.x - q.x) <= tolerance && std::fabs(p.y - q.y) <= tolerance;
}

namespace {

// The first i of [1, n) with the largest |key(i)| (0 and 0 if none is
// above 0), by chunks: each chunk's first largest, then the first chunk's
// of the largest, as one pass in order would find it.
template <typename Key>
std::pair<std::size_t, int64_t> FirstLargest(const Execution& execution, std::size_t n, const Key& key) {
  const int chunks = ChunksFor(static_cast<int64_t>(n), 1 << 16);
  std::vector<std::pair<std::size_t, int64_t>> best(chunks, {0, 0});
  ForEachChunk(execution, static_cast<int64_t>(n), chunks, [&](int c, int64_t begin, int64_t end) {
    for (int64_t i = std::max<int64_t>(begin, 1); i < end; ++i) {
      const int64_t k = key(static_cast<std::size_t>(i));
      if (std::llabs(k) > std::llabs(best[c].second)) best[c] = {static_cast<std::size_t>(i), k};
    }
  });
  std::pair<std::size_t, int64_t> first = {0, 0};
  for (const auto& b : best) {
    if (std::llabs(b.second) > std::llabs(first.second)) first = b;
  }
  return first;
}

}  // namespace

bool FitAffine(const Surface& s, double magnitude, GridAffine* fit, double* tolerance,
               const Execution& execution) {
  const std::vector<RasterCell>& cells = s.raster_cell;
  const int64_t c0 = cells[0].column, r0 = cells[0].row;
  const std::size_t i1 = FirstLargest(execution, cells.size(), [&](std::size_t i) {
    return std::llabs(cells[i].column - c0) + std::llabs(cells[i].row - r0);
  }).first;
  const int64_t dc1 = cells[i1].column - c0, dr1 = cells[i1].row - r0;
  const auto [i2, det] = FirstLargest(execution, cells.size(), [&](std::size_t i) {
    return dc1 * (cells[i].row - r0) - dr1 * (cells[i].column - c0);
  });
  if (det == 0) return false;  // all samples on one line of cells
  const int64_t dc2 = cells[i2].column - c0, dr2 = cells[i2].row - r0;
  const Point2 p0 = s.xy[0], p1 = s.xy[i1], p2 = s.xy[i2];
  const Point2 e1{p1.x - p0.x, p1.y - p0.y}, e2{p2.x - p0.x, p2.y - p0.y};
  const double inv = 1.0 / static_cast<double>(det);
  fit->origin = p0, fit->c0 = c0, fit->r0 = r0;
  fit->u = {(dr2 * e1.x - dr1 * e2.x) * inv, (dr2 * e1.y - dr1 * e2.y) * inv};
  fit->v = {(dc1 * e2.x - dc2 * e1.x) * inv, (dc1 * e2.y - dc2 * e1.y) * inv};
  const double lu = std::hypot(fit->u.x, fit->u.y), lv = std::hypot(fit->v.x, fit->v.y);
  const double cross = fit->u.x * fit->v.y - fit->u.y * fit->v.x;
  if (!(std::fabs(cross) > 1e-6 * lu * lv)) return false;
  *tolerance = 64.0 * std::numeric_limits<double>::epsilon() * magnitude + 1e-9 * std::min(lu, lv);
  const int chunks = ChunksFor(static_cast<int64_t>(cells.size()), 1 << 16);
  std::vector<uint8_t> near(chunks, 1);
  ForEachChunk(execution, static_cast<int64_t>(cells.size()), chunks, [&](int c, int64_t begin, int64_t end) {
    bool all_near = true;  // a local: the chunks' slots share cache lines
    for (int64_t i = begin; i < end && all_near; ++i) {
      all_near = Near(fit->At(cells[i].column, cells[i].row), s.xy[i], *tolerance);
    }
    near[c] = all_near;
  });
  return std::all_of(near.begin(), near.end(), [](uint8_t v) { return v != 0; });
}

double Magnitude(const Surface& s, const Execution& execution) {
  const int chunks = ChunksFor(static_cast<int64_t>(s.xy.size()), 1 << 16);
  std::vector<double> most(chunks, 0.0);
  ForEachChunk(execution, static_cast<int64_t>(s.xy.size()), chunks, [&](int c, int64_t begin, int64_t end) {
    double largest = 0.0;
    for (int64_t i = begin; i < end; ++i) largest = std::max({largest, std::fabs(s.xy[i].x), std::fabs(s.xy[i].y)});
    most[c] = largest;
  });
  return *std::max_element(most.begin(), most.end()) + std::max(std::fabs(s.origin[0]), std::fabs(s.origin[1]));
}

// The area of the convex hull of a grid's samples: each row's samples are
// on one line, so its two ends stand for it; the hull is taken in index
// space, exactly in integers (rows of collinear ends would send every
// floating-point orientation test to the exact stage), times a cell's area.
__extension__ typedef __int128 Wide;  // products of two index differences, exactly

double HullArea(const GridIndex& index, double cell_area) {
  std::vector<std::array<int64_t, 2>> ends;
  for (int64_t r = 0; r < index.rows; ++r) {
    const int32_t* row = &index.sample[static_cast<std::size_t>(r * index.columns)];
    int64_t first = 0, last = index.columns - 1;
    while (first <= last && row[first] < 0) ++first;
    while (last > first && row[last] < 0) --last;
    if (first > last) continue;
    ends.push_back({first, r});
    if (last != first) ends.push_back({last, r});
  }
  return HullAreaOfRowEnds(std::move(ends), cell_area);
}

double HullAreaOfRowEnds(std::vector<std::array<int64_t, 2>> ends, double cell_area) {
  using Corner = std::array<int64_t, 2>;
  std::sort(ends.begin(), ends.end());
  const auto turn = [](const Corner& o, const Corner& p, const Corner& q) {
    return static_cast<Wide>(p[0] - o[0]) * (q[1] - o[1]) - static_cast<Wide>(p[1] - o[1]) * (q[0] - o[0]);
  };
  std::vector<Corner> hull(2 * ends.size() + 1);
  std::size_t k = 0;
  for (std::size_t i = 0; i < ends.size(); ++i) {  // lower chain, then upper (Andrew)
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], ends[i]) <= 0) --k;
    hull[k++] = ends[i];
  }
  for (std::size_t i = ends.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], ends[i]) <= 0) --k;
    hull[k++] = ends[i];
  }
  Wide twice = 0;
  for (std::size_t i = 0; i + 1 < k; ++i) {
    twice += static_cast<Wide>(hull[i][0]) * hull[i + 1][1] - static_cast<Wide>(hull[i + 1][0]) * hull[i][1];
  }
  return 0.5 * static_cast<double>(twice < 0 ? -twice : twice) * cell_area;
}

bool MarkComplete(GridSide* side, int64_t begin, int64_t end, double sign, double* area) {
  double twice = 0.0;
  bool ok = true;
  const int64_t columns = side->index.columns;
  for (int64_t r = begin; r < end; ++r) {
    uint8_t* flags = &side->complete[static_cast<std::size_t>(r * columns)];
    const int32_t* here = side->SampleRow(r);
    const int32_t* below = side->SampleRow(r + 1);
    if (below == nullptr) continue;  // the last row starts no cell
    for (int64_t c = 0; c + 1 < columns; ++c) {
      int32_t k[4];
      GridSide::Corners(here, below, c, k);
      if (k[0] < 0 || k[1] < 0 || k[2] < 0 || k[3] < 0) continue;
      flags[c] = 1;
      const Point2 p[4] = {side->Xy(k[0]), side->Xy(k[1]), side->Xy(k[2]), side->Xy(k[3])};
      const double o1 = Orient2D(p[0], p[1], p[2]), o2 = Orient2D(p[0], p[2], p[3]);
      if (!(o1 * sign > 0.0 && o2 * sign > 0.0)) ok = false;
      twice += std::fabs(TwiceArea(p[0], p[1], p[2])) + std::fabs(TwiceArea(p[0], p[2], p[3]));
    }
  }
  *area = 0.5 * twice;
  return ok;
}

namespace {

// ∫ max(e, 0) and the area where e > 0 over a triangle of area `area` on
// which e is linear with corner values e[0..2]: the part where e > 0 is the
// triangle itself, a corner's triangle cut off by the line e = 0 (its share
// of the area the product of the two edge fractions), or the triangle less
// such a corner; so the clip of the general overlay in closed form.
struct PositivePart {
  double integral = 0, area = 0;
};
PositivePart PositiveOver(double area, const double e[3]) {
  const int above = (e[0] > 0.0) + (e[1] > 0.0) + (e[2] > 0.0);
  if (above == 0) return {};
  if (above == 3) return {area * (e[0] + e[1] + e[2]) / 3.0, area};
  // The lone corner: the one above (one above) or the one not (two above).
  const int k = above == 1 ? (e[0] > 0.0 ? 0 : e[1] > 0.0 ? 1 : 2) : (e[0] <= 0.0 ? 0 : e[1] <= 0.0 ? 1 : 2);
  const double lone = e[k], o1 = e[(k + 1) % 3], o2 = e[(k + 2) % 3];
  const double corner = area * (lone / (lone - o1)) * (lone / (lone - o2));  // where e has lone's sign
  if (above == 1) return {corner * lone / 3.0, corner};
  return {area * (e[0] + e[1] + e[2]) / 3.0 - corner * lone / 3.0, area - corner};
}

}  // namespace

void IntegrateTriangle(const Point2 p[3], const double d[3], double lod, VolumeResult* result) {
  IntegrateTriangleOfArea(0.5 * TwiceArea(p[0], p[1], p[2]), d, lod, result);
}

void IntegrateTriangleOfArea(double area, const double d[3], double lod, VolumeResult* result) {
  if (!(area > 0.0)) return;
  result->gap += IntegrateGap(area, d[0], d[1], d[2]);
  result->area += area;
  if (lod < 0.0) return;
  const double fill_e[3] = {d[0] - lod, d[1] - lod, d[2] - lod};
  const double cut_e[3] = {-d[0] - lod, -d[1] - lod, -d[2] - lod};
  const PositivePart fill = PositiveOver(area, fill_e), cut = PositiveOver(area, cut_e);
  // ∫_{d > L} d = ∫ max(d − L, 0) + L · |{d > L}|, and so for the cut.
  result->change.fill += fill.integral + lod * fill.area;
  result->change.fill_area += fill.area;
  result->change.cut += cut.integral + lod * cut.area;
  result->change.cut_area += cut.area;
}


int RowChunks(int64_t rows) { return ChunksFor(rows, 16); }

bool MarkBoth(GridSide* a, GridSide* b, double sign, const Execution& execution, double* area_a,
              double* area_b) {
  a->complete.assign(a->index.sample.size(), 0);
  b->complete.assign(b->index.sample.size(), 0);
  const auto mark = [&](GridSide* side, double* total) {
    const int chunks = RowChunks(side->index.rows);
    std::vector<double> area(chunks, 0.0);
    std::vector<uint8_t> ok(chunks, 1);
    ForEachChunk(execution, side->index.rows, chunks, [&](int c, int64_t begin, int64_t end) {
      ok[c] = MarkComplete(side, begin, end, sign, &area[c]);
    });
    *total = 0.0;
    for (int c = 0; c < chunks; ++c) *total += area[c];
    return std::all_of(ok.begin(), ok.end(), [](uint8_t v) { return v != 0; });
  };
  const bool ok_a = mark(a, area_a);
  const bool ok_b = mark(b, area_b);
  return ok_a && ok_b;
}

std::vector<double> NodeAreas(const GridSide& side_a, const Surface& a, const std::vector<uint8_t>& omega,
                              const Execution& execution) {
  std::vector<double> node_area(a.size(), 0.0);
  const int64_t rows = side_a.index.rows, columns = side_a.index.columns;
  // Gathered per node from the (up to) four cells around it, in the order
  // a sweep of the cells row by row would add their triangles' thirds: the
  // same sums, with each node written by one chunk of rows only. Each
  // triangle's third is computed once, into a rolling pair of cell rows
  // (0 for a triangle outside the domain or with a corner outside Ω).
  static constexpr int kTriangles[2][3] = {{0, 1, 2}, {0, 2, 3}};
  // The cells (dr, dc) relative to the node, row-major, and which of the
  // cell's two triangles have the node's corner (GridSide::Corners).
  struct Around {
    int dr, dc;
    bool first, second;
  };
  static constexpr Around kAround[4] = {
      {-1, -1, true, true}, {-1, 0, false, true}, {0, -1, true, false}, {0, 0, true, true}};
  const auto thirds_of_row = [&](int64_t cr, double* out) {
    // Cells of row cr (two thirds each); zeros outside the index.
    std::fill(out, out + 2 * columns, 0.0);
    if (cr < 0 || cr + 1 >= rows) return;
    const uint8_t* complete = side_a.CompleteRow(cr);
    const int32_t* here = side_a.SampleRow(cr);
    const int32_t* below = side_a.SampleRow(cr + 1);
    for (int64_t cc = 0; cc + 1 < columns; ++cc) {
      if (!complete[cc]) continue;
      int32_t k[4];
      GridSide::Corners(here, below, cc, k);
      for (int j = 0; j < 2; ++j) {
        const int* t = kTriangles[j];
        if (!omega[k[t[0]]] || !omega[k[t[1]]] || !omega[k[t[2]]]) continue;
        out[2 * cc + j] = std::fabs(Orient2D(a.xy[k[t[0]]], a.xy[k[t[1]]], a.xy[k[t[2]]])) / 6.0;
      }
    }
  };
  ForEachChunk(execution, rows, RowChunks(rows), [&](int, int64_t begin, int64_t end) {
    // One allocation per chunk, not per node: the cell rows above and at r.
    std::vector<double> above(2 * columns), here(2 * columns);
    thirds_of_row(begin - 1, above.data());
    for (int64_t r = begin; r < end; ++r) {
      thirds_of_row(r, here.data());
      const int32_t* row = side_a.SampleRow(r);
      for (int64_t c = 0; c < columns; ++c) {
        if (row[c] < 0) continue;
        double sum = 0.0;
        for (const Around& cell : kAround) {
          const int64_t cc = c + cell.dc;
          if (cc < 0 || cc + 1 >= columns) continue;
          const double* thirds = (cell.dr < 0 ? above.data() : here.data()) + 2 * cc;
          // A triangle outside adds +0.0, which leaves every sum's bits as
          // they were without it.
          if (cell.first) sum += thirds[0];
          if (cell.second) sum += thirds[1];
        }
        node_area[row[c]] = sum;
      }
      above.swap(here);
    }
  });
  return node_area;
}

bool IndexSides(const Surface& a, const Surface& b, const Execution& execution, GridSide* side_a,
                GridSide* side_b) {
  side_a->surface = &a, side_b->surface = &b;
  side_b->shift = {b.origin[0] - a.origin[0], b.origin[1] - a.origin[1]};
  side_b->z_shift = b.origin[2] - a.origin[2];
  return BuildIndex(a.raster_cell, &side_a->index, execution) && BuildIndex(b.raster_cell, &side_b->index, execution);
}

ChunkSums SumChunks(const std::vector<ChunkSums>& parts) {
  ChunkSums total;
  for (const ChunkSums& part : parts) {
    total.volume.gap += part.volume.gap;
    total.volume.change += part.volume.change;
    total.volume.area += part.volume.area;
    total.volume.cells += part.volume.cells;
    total.gap_sum += part.gap_sum;
    total.node_weight += part.node_weight;
    total.nodes += part.nodes;
  }
  return total;
}

void FinishResult(const std::vector<ChunkSums>& parts, const GridSide& side_a, const GridSide& side_b,
                  const std::vector<uint8_t>& omega_a, bool keep, const Execution& execution,
                  GridPairResult* result) {
  const ChunkSums total = SumChunks(parts);
  result->volume = total.volume;
  const double gap_sum = total.gap_sum, node_weight = total.node_weight;
  const int64_t nodes = total.nodes;
  result->rho_d_axial = node_weight > 0.0 ? gap_sum / node_weight : 0.0;
  result->n_overlap_nodes = nodes;
  result->hull_area_a = HullArea(side_a.index, side_a.cell_area);
  result->hull_area_b = HullArea(side_b.index, side_b.cell_area);
  if (keep) result->node_area_a = NodeAreas(side_a, *side_a.surface, omega_a, execution);
}

std::array<double, 3> RuleWeights(int h, double x, double y) {
  if (h == 0) return {1.0 - x, x - y, y};  // (0,0) (1,0) (1,1)
  return {1.0 - y, x, y - x};              // (0,0) (1,1) (0,1)
}

std::vector<Piece> PiecePattern(double fx, double fy) {
  std::vector<Piece> pieces;
  for (int a = 0; a < 2; ++a) {
    const Point2 ta[3] = {{kCorner[kRule[a][0]][0], kCorner[kRule[a][0]][1]},
                          {kCorner[kRule[a][1]][0], kCorner[kRule[a][1]][1]},
                          {kCorner[kRule[a][2]][0], kCorner[kRule[a][2]][1]}};
    for (int dr = 0; dr < 2; ++dr) {
      for (int dc = 0; dc < 2; ++dc) {
        for (int b = 0; b < 2; ++b) {
          std::array<Point2, 3> tb;
          for (int k = 0; k < 3; ++k) {
            tb[k] = {dc - fx + kCorner[kRule[b][k]][0], dr - fy + kCorner[kRule[b][k]][1]};
          }
          Point2 out[9];
          const int m = ClipByTriangle(ta, 3, tb, out);
          if (m < 3) continue;
          Piece piece;
          piece.a = a, piece.b = b, piece.dc = dc, piece.dr = dr, piece.corners = m;
          double total = 0.0;
          for (int k = 1; k + 1 < m; ++k) {
            piece.fan[k - 1] = 0.5 * TwiceArea(out[0], out[k], out[k + 1]);
            total += piece.fan[k - 1];
          }
          if (!(total > 1e-12)) continue;  // B's triangle only touches A's
          for (int k = 0; k < m; ++k) {
            const std::array<double, 3> wa = RuleWeights(a, out[k].x, out[k].y);
            const std::array<double, 3> wb = RuleWeights(b, out[k].x - dc + fx, out[k].y - dr + fy);
            for (int i = 0; i < 4; ++i) piece.wa[k][i] = piece.wb[k][i] = 0.0;
            for (int i = 0; i < 3; ++i) piece.wa[k][kRule[a][i]] = wa[i], piece.wb[k][kRule[b][i]] = wb[i];
          }
          pieces.push_back(piece);
        }
      }
    }
  }
  return pieces;
}


void IntegratePieces(const std::vector<Piece>& pieces, const double za[4], const double zb[2][2][4],
                     const bool whole[2][2], double cell_area, double lod, VolumeResult* volume) {
  for (const Piece& piece : pieces) {
    if (!whole[piece.dr][piece.dc]) continue;
    const double* z = zb[piece.dr][piece.dc];
    double d[9];
    for (int v = 0; v < piece.corners; ++v) {
      const double* wa = piece.wa[v];
      const double* wb = piece.wb[v];
      d[v] = (wb[0] * z[0] + wb[1] * z[1] + wb[2] * z[2] + wb[3] * z[3]) -
             (wa[0] * za[0] + wa[1] * za[1] + wa[2] * za[2] + wa[3] * za[3]);
    }
    for (int v = 1; v + 1 < piece.corners; ++v) {
      const double gaps[3] = {d[0], d[v], d[v + 1]};
      IntegrateTriangleOfArea(cell_area * piece.fan[v - 1], gaps, lod, volume);
    }
    ++volume->cells;
  }
}

}  // namespace grid_cells
}  // namespace surfreg

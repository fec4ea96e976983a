#include "measure/grid_pair.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "measure/convex_hull.h"
#include "measure/predicates.h"
#include "measure/run_both.h"
#include "measure/volume.h"
#include "measure/weights.h"

namespace surfreg {
namespace {

// A surface's samples by cell: a dense row-major index over the bounding
// box of its cells.
struct GridIndex {
  int64_t c0 = 0, r0 = 0, columns = 0, rows = 0;
  std::vector<int32_t> sample;  // -1: no sample

  int32_t At(int64_t c, int64_t r) const {
    c -= c0, r -= r0;
    if (c < 0 || r < 0 || c >= columns || r >= rows) return -1;
    return sample[static_cast<std::size_t>(r * columns + c)];
  }
};

// A box this much larger than the samples would cost more memory than the
// general path saves: a sparse raster is left to it.
constexpr int64_t kMaxBoxPerSample = 16;

// False for a repeated cell or a box too sparse for a dense index.
bool BuildIndex(const std::vector<RasterCell>& cells, GridIndex* index) {
  int64_t c_lo = cells[0].column, c_hi = c_lo, r_lo = cells[0].row, r_hi = r_lo;
  for (const RasterCell& cell : cells) {
    c_lo = std::min<int64_t>(c_lo, cell.column), c_hi = std::max<int64_t>(c_hi, cell.column);
    r_lo = std::min<int64_t>(r_lo, cell.row), r_hi = std::max<int64_t>(r_hi, cell.row);
  }
  index->c0 = c_lo, index->r0 = r_lo;
  index->columns = c_hi - c_lo + 1, index->rows = r_hi - r_lo + 1;
  const int64_t most = kMaxBoxPerSample * static_cast<int64_t>(cells.size()) + 4096;
  if (index->columns > most || index->rows > most || index->rows > most / index->columns) {
    return false;
  }
  index->sample.assign(static_cast<std::size_t>(index->rows * index->columns), -1);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    int32_t& slot = index->sample[static_cast<std::size_t>((cells[i].row - index->r0) * index->columns +
                                                            (cells[i].column - index->c0))];
    if (slot >= 0) return false;
    slot = static_cast<int32_t>(i);
  }
  return true;
}

// Positions as an affine function of the cell: origin at cell (c0, r0), u
// per column, v per row.
struct GridAffine {
  Point2 origin, u, v;
  int64_t c0 = 0, r0 = 0;
  Point2 At(int64_t c, int64_t r) const {
    const double dc = static_cast<double>(c - c0), dr = static_cast<double>(r - r0);
    return {origin.x + dc * u.x + dr * v.x, origin.y + dc * u.y + dr * v.y};
  }
};

bool Near(const Point2& p, const Point2& q, double tolerance) {
  return std::fabs(p.x - q.x) <= tolerance && std::fabs(p.y - q.y) <= tolerance;
}

// The affine function through three samples far apart, if every sample is
// on it to `*tolerance` (set here: rounding of the input coordinates, of
// magnitude `magnitude`, plus 1e-9 of a cell).
bool FitAffine(const Surface& s, double magnitude, GridAffine* fit, double* tolerance) {
  const std::vector<RasterCell>& cells = s.raster_cell;
  const int64_t c0 = cells[0].column, r0 = cells[0].row;
  std::size_t i1 = 0, i2 = 0;
  int64_t far = 0, det = 0;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    const int64_t d = std::llabs(cells[i].column - c0) + std::llabs(cells[i].row - r0);
    if (d > far) far = d, i1 = i;
  }
  const int64_t dc1 = cells[i1].column - c0, dr1 = cells[i1].row - r0;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    const int64_t d = dc1 * (cells[i].row - r0) - dr1 * (cells[i].column - c0);
    if (std::llabs(d) > std::llabs(det)) det = d, i2 = i;
  }
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
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (!Near(fit->At(cells[i].column, cells[i].row), s.xy[i], *tolerance)) return false;
  }
  return true;
}

double Magnitude(const Surface& s) {
  double m = 0.0;
  for (const Point2& p : s.xy) m = std::max({m, std::fabs(p.x), std::fabs(p.y)});
  return m + std::max(std::fabs(s.origin[0]), std::fabs(s.origin[1]));
}

// The area of the convex hull of a grid's samples: each row's samples are
// on one line, so its two ends stand for it.
double HullArea(const std::vector<Point2>& xy, const GridIndex& index, Point2 shift) {
  std::vector<Point2> ends;
  for (int64_t r = 0; r < index.rows; ++r) {
    const int32_t* row = &index.sample[static_cast<std::size_t>(r * index.columns)];
    int64_t first = 0, last = index.columns - 1;
    while (first <= last && row[first] < 0) ++first;
    while (last > first && row[last] < 0) --last;
    if (first > last) continue;
    ends.push_back({xy[row[first]].x + shift.x, xy[row[first]].y + shift.y});
    if (last != first) ends.push_back({xy[row[last]].x + shift.x, xy[row[last]].y + shift.y});
  }
  return PolygonArea(ConvexHull(std::move(ends)));
}

// One surface on the grid: its index, positions in A's frame and heights.
struct GridSide {
  const Surface* surface = nullptr;
  GridIndex index;
  Point2 shift;        // added to the surface's xy (B's origin minus A's)
  double z_shift = 0;  // added to its z
  std::vector<uint8_t> complete;  // per index cell: its four corners are samples
  double domain_area = 0;

  Point2 Xy(int32_t i) const {
    const Point2& p = surface->xy[i];
    return shift.x == 0.0 && shift.y == 0.0 ? p : Point2{p.x + shift.x, p.y + shift.y};
  }
  double Z(int32_t i) const { return surface->z[i] + z_shift; }
  // Rows of the index and of the completeness flags (null outside it).
  const int32_t* SampleRow(int64_t r) const {
    return r < 0 || r >= index.rows ? nullptr : &index.sample[static_cast<std::size_t>(r * index.columns)];
  }
  const uint8_t* CompleteRow(int64_t r) const {
    return r < 0 || r >= index.rows ? nullptr : &complete[static_cast<std::size_t>(r * index.columns)];
  }
  // The corners (c, r) (c+1, r) (c+1, r+1) (c, r+1) of cell c of the rows
  // `here` and `below` (index coordinates; c + 1 inside the row).
  static void Corners(const int32_t* here, const int32_t* below, int64_t c, int32_t k[4]) {
    k[0] = here[c], k[1] = here[c + 1], k[2] = below[c + 1], k[3] = below[c];
  }
  // A corner of a complete cell (the cells c − 1 and c of the rows r − 1
  // and r, flags `above` and `here`): a vertex of the data domain.
  bool DomainVertex(const uint8_t* above, const uint8_t* here, int64_t c) const {
    const auto complete_at = [this](const uint8_t* row, int64_t k) {
      return row != nullptr && k >= 0 && k < index.columns && row[k] != 0;
    };
    return complete_at(above, c - 1) || complete_at(above, c) || complete_at(here, c - 1) ||
           complete_at(here, c);
  }
};

// Rows [begin, end) of a side: completeness, orientation and the domain's
// area. False if a complete cell's triangle does not have the sign `sign`
// (a fold or a degenerate cell).
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

// One grid triangle (counter-clockwise corners p, gaps d) with μ = 1: the
// overlay cell integrator's results (IntegrateConvex, uniform) in closed form.
void IntegrateTriangle(const Point2 p[3], const double d[3], double lod, VolumeResult* result) {
  const double area = 0.5 * TwiceArea(p[0], p[1], p[2]);
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

struct HalfSums {
  VolumeResult volume;
  double gap_sum = 0, node_weight = 0;
  int64_t nodes = 0;
};

}  // namespace

bool MeasureOnSameGrid(const Surface& a, const Surface& b, const MeasureOptions& options,
                       GridPairResult* out) {
  if (!options.grid_shortcut || !a.raster_grid() || !b.raster_grid() || options.volume != VolumeMode::kOverlay ||
      options.domain.kind != DomainKind::kData || options.weight == WeightMode::kPerPoint) {
    return false;
  }
  GridSide sa, sb;
  sa.surface = &a, sb.surface = &b;
  sb.shift = {b.origin[0] - a.origin[0], b.origin[1] - a.origin[1]};
  sb.z_shift = b.origin[2] - a.origin[2];
  if (!BuildIndex(a.raster_cell, &sa.index) || !BuildIndex(b.raster_cell, &sb.index)) return false;
  GridAffine grid;
  double tolerance = 0.0;
  if (!FitAffine(a, std::max(Magnitude(a), Magnitude(b)), &grid, &tolerance)) return false;

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

  // Completeness and orientation, each side in two halves of its rows.
  const double sign = cross > 0.0 ? 1.0 : -1.0;
  sa.complete.assign(sa.index.sample.size(), 0);
  sb.complete.assign(sb.index.sample.size(), 0);
  bool ok[4] = {true, true, true, true};
  double area[4] = {0, 0, 0, 0};
  const int64_t mid_a = sa.index.rows / 2, mid_b = sb.index.rows / 2;
  RunBoth(options.parallel,
          [&] {
            ok[0] = MarkComplete(&sa, 0, mid_a, sign, &area[0]);
            ok[1] = MarkComplete(&sb, 0, mid_b, sign, &area[1]);
          },
          [&] {
            ok[2] = MarkComplete(&sa, mid_a, sa.index.rows, sign, &area[2]);
            ok[3] = MarkComplete(&sb, mid_b, sb.index.rows, sign, &area[3]);
          });
  if (!(ok[0] && ok[1] && ok[2] && ok[3])) return false;
  GridPairResult& result = *out;
  result = GridPairResult();
  result.domain_area_a = area[0] + area[2];
  result.domain_area_b = area[1] + area[3];

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
  const auto rows = [&](int64_t begin, int64_t end, HalfSums* sums) {
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
  HalfSums half[2];
  RunBoth(options.parallel, [&] { rows(0, mid_a, &half[0]); },
          [&] { rows(mid_a, sa.index.rows, &half[1]); });
  VolumeResult& volume = result.volume;
  for (const HalfSums& h : half) {
    volume.gap += h.volume.gap;
    volume.change += h.volume.change;
    volume.area += h.volume.area;
    volume.cells += h.volume.cells;
  }
  const double node_weight = half[0].node_weight + half[1].node_weight;
  result.rho_d_axial = node_weight > 0.0 ? (half[0].gap_sum + half[1].gap_sum) / node_weight : 0.0;
  result.n_overlap_nodes = half[0].nodes + half[1].nodes;
  result.hull_area_a = HullArea(a.xy, sa.index, {0.0, 0.0});
  result.hull_area_b = HullArea(b.xy, sb.index, sb.shift);

  if (keep) {  // a third of each of A's domain triangles with its corners in Ω
    result.node_area_a.assign(a.size(), 0.0);
    for (int64_t r = 0; r + 1 < sa.index.rows; ++r) {
      const uint8_t* flags = sa.CompleteRow(r);
      const int32_t* here = sa.SampleRow(r);
      const int32_t* below = sa.SampleRow(r + 1);
      for (int64_t c = 0; c + 1 < sa.index.columns; ++c) {
        if (!flags[c]) continue;
        int32_t k[4];
        GridSide::Corners(here, below, c, k);
        const int triangles[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (const auto& t : triangles) {
          if (!omega[k[t[0]]] || !omega[k[t[1]]] || !omega[k[t[2]]]) continue;
          const double third = std::fabs(Orient2D(a.xy[k[t[0]]], a.xy[k[t[1]]], a.xy[k[t[2]]])) / 6.0;
          for (int m = 0; m < 3; ++m) result.node_area_a[k[t[m]]] += third;
        }
      }
    }
  }
  return true;
}

}  // namespace surfreg

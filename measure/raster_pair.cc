#include "measure/raster_pair.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "measure/grid_cells.h"
#include "measure/grid_pair.h"
#include "measure/predicates.h"
#include "measure/tasks.h"

namespace surfreg {

using namespace grid_cells;

namespace {

// One raster's cells: validity, positions (RasterBlockToSurface's doubles)
// and its box of valid cells.
struct Side {
  const RasterHeights* raster = nullptr;
  Point2 origin;            // subtracted from positions
  double z_origin = 0.0;    // subtracted from heights
  int64_t c_lo = 0, c_hi = -1, r_lo = 0, r_hi = -1;  // the box of valid cells (empty: c_hi < c_lo)
  std::vector<int64_t> row_start;  // valid cells before each row: the sample numbering
  std::vector<std::array<int64_t, 2>> row_ends;  // each row's first and last valid column (-1: none)
  int64_t samples = 0;

  bool Valid(int64_t c, int64_t r) const {
    return c >= 0 && r >= 0 && c < raster->columns && r < raster->rows &&
           std::isfinite(raster->z[static_cast<std::size_t>(r * raster->columns + c)]);
  }
  double Z(int64_t c, int64_t r) const {
    return raster->z[static_cast<std::size_t>(r * raster->columns + c)] - z_origin;
  }
  Point2 Xy(int64_t c, int64_t r) const {
    const auto& g = raster->geotransform;
    const double cc = static_cast<double>(c) + 0.5, rr = static_cast<double>(r) + 0.5;
    return {g[0] + cc * g[1] + rr * g[2] - origin.x, g[3] + cc * g[4] + rr * g[5] - origin.y};
  }
  // Cells (c, r) of row r, c in [0, columns): complete when the corners
  // (c, r) (c+1, r) (c+1, r+1) (c, r+1) are valid; 0 outside the raster.
  void CompleteRow(int64_t r, uint8_t* out) const {
    const int64_t columns = raster->columns;
    std::fill(out, out + columns, uint8_t{0});
    if (r < 0 || r + 1 >= raster->rows) return;
    const double* here = raster->z + r * columns;
    const double* below = here + columns;
    for (int64_t c = 0; c + 1 < columns; ++c) {
      out[c] = static_cast<uint8_t>(std::isfinite(here[c]) & std::isfinite(here[c + 1]) &
                                    std::isfinite(below[c]) & std::isfinite(below[c + 1]));
    }
  }
  int64_t BoxRows() const { return r_hi - r_lo + 1; }
};

// A corner (c, r) of a complete cell (the flags of the rows r − 1 and r): a
// vertex of the data domain.
inline bool DomainVertex(const uint8_t* above, const uint8_t* here, int64_t c, int64_t columns) {
  const bool left = c >= 1, inside = c < columns;
  return (left && (above[c - 1] | here[c - 1])) || (inside && (above[c] | here[c]));
}

// Rows' counts and ends in parallel (each row written by one chunk), then
// the box and the numbering; false for a height beyond kMaxCoordinate.
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
  if (!std::all_of(in_range.begin(), in_range.end(), [](uint8_t v) { return v != 0; })) return false;
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

// The domain's area as MarkComplete sums it: the complete cells' two
// triangles, row chunks of the box, the chunks' halves added in order.
double DomainArea(const Execution& execution, const Side& side, int64_t* complete_cells) {
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
  ForEachChunk(execution, rows, chunks, [&](int chunk, int64_t begin, int64_t end) {
    double twice = 0.0;
    std::vector<uint8_t> complete(static_cast<std::size_t>(side.raster->columns));
    for (int64_t r = side.r_lo + begin; r < side.r_lo + end && r < side.r_hi; ++r) {
      side.CompleteRow(r, complete.data());
      const double dy = side.Xy(0, r + 1).y - side.Xy(0, r).y;
      for (int64_t c = side.c_lo; c < side.c_hi; ++c) {
        if (!complete[c]) continue;
        ++cells[chunk];
        if (north_up) {
          const double t = std::fabs(dx[c] * dy);
          twice += t + t;
          continue;
        }
        const Point2 p[4] = {side.Xy(c, r), side.Xy(c + 1, r), side.Xy(c + 1, r + 1), side.Xy(c, r + 1)};
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

// A third of each of A's domain triangles whose corners are all in Ω (its
// dz finite), per sample: NodeAreas' sums, in its order, without an index.
std::vector<double> NodeAreasOf(const Execution& execution, const Side& a, const std::vector<double>& dz_a) {
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
    const auto thirds_of_row = [&](int64_t r, const int64_t* top, const int64_t* bottom, double* out) {
      std::fill(out, out + 2 * columns, 0.0);
      if (r < a.r_lo || r >= a.r_hi) return;
      for (int64_t c = a.c_lo; c < a.c_hi; ++c) {
        const int64_t k[4] = {top[c], top[c + 1], bottom[c + 1], bottom[c]};
        if (k[0] < 0 || k[1] < 0 || k[2] < 0 || k[3] < 0) continue;
        const Point2 p[4] = {a.Xy(c, r), a.Xy(c + 1, r), a.Xy(c + 1, r + 1), a.Xy(c, r + 1)};
        static constexpr int kTriangles[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int j = 0; j < 2; ++j) {
          const int* t = kTriangles[j];
          if (!std::isfinite(dz_a[k[t[0]]]) || !std::isfinite(dz_a[k[t[1]]]) || !std::isfinite(dz_a[k[t[2]]])) {
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

}  // namespace

bool MeasureRasterPair(const RasterHeights& ra, const RasterHeights& rb, const std::array<double, 3>& origin,
                       const MeasureOptions& options, MeasureSummary* out, bool node_areas) {
  std::string error;
  if (!options.grid_shortcut || options.volume != VolumeMode::kOverlay || options.domain.kind != DomainKind::kData ||
      options.weight != WeightMode::kUniform || !options.IsValid(&error)) {
    return false;
  }
  if (ra.z == nullptr || rb.z == nullptr || ra.columns <= 0 || ra.rows <= 0 || rb.columns <= 0 || rb.rows <= 0) {
    return false;
  }
  // The same cell vectors, non-degenerate (as FitAffine asks).
  const auto& ga = ra.geotransform;
  const auto& gb = rb.geotransform;
  if (ga[1] != gb[1] || ga[2] != gb[2] || ga[4] != gb[4] || ga[5] != gb[5]) return false;
  const Point2 u{ga[1], ga[4]}, v{ga[2], ga[5]};
  const double cross = u.x * v.y - u.y * v.x;
  if (!(std::fabs(cross) > 1e-6 * std::hypot(u.x, u.y) * std::hypot(v.x, v.y)) || !std::isfinite(cross)) return false;
  for (const auto* g : {&ga, &gb}) {
    for (const double x : *g) {
      if (!std::isfinite(x)) return false;
    }
  }
  // B's cell (c, r) is A's (c + dc, r + dr).
  const double ex = gb[0] - ga[0], ey = gb[3] - ga[3];
  const double fc = (ex * v.y - ey * v.x) / cross, fr = (u.x * ey - u.y * ex) / cross;
  if (!(std::fabs(fc) < 1e9 && std::fabs(fr) < 1e9)) return false;
  if (std::fabs(fc - std::round(fc)) > 1e-6 || std::fabs(fr - std::round(fr)) > 1e-6) return false;
  const int64_t dc = std::llround(fc), dr = std::llround(fr);

  const auto start = std::chrono::steady_clock::now();
  if (options.on_progress) {
    options.on_progress({"volume (one grid)", 0.6, 0.0, static_cast<int64_t>(ra.columns * ra.rows + rb.columns * rb.rows)});
  }
  const Execution execution = ExecutionFor(options.threads);
  Side a, b;
  a.raster = &ra, b.raster = &rb;
  a.origin = b.origin = {origin[0], origin[1]};
  a.z_origin = b.z_origin = origin[2];
  bool scanned_a = false, scanned_b = false;
  RunBoth(execution, [&] { scanned_a = Scan(execution, &a); }, [&] { scanned_b = Scan(execution, &b); });
  if (!scanned_a || !scanned_b) return false;
  // Positions within kMaxCoordinate (ValidateSurface): the boxes' corners.
  for (const Side* s : {&a, &b}) {
    for (const int64_t c : {s->c_lo, s->c_hi}) {
      for (const int64_t r : {s->r_lo, s->r_hi}) {
        const Point2 p = s->Xy(c, r);
        if (!(std::fabs(p.x + origin[0]) <= kMaxCoordinate && std::fabs(p.y + origin[1]) <= kMaxCoordinate)) {
          return false;
        }
      }
    }
  }
  GridPairResult result;
  int64_t complete_a = 0, complete_b = 0;
  RunBoth(
      execution, [&] { result.domain_area_a = DomainArea(execution, a, &complete_a); },
      [&] { result.domain_area_b = DomainArea(execution, b, &complete_b); });
  if (complete_a == 0 || complete_b == 0) return false;  // Measure names the surface with no data

  const double lod = options.detect_change ? options.level_of_detection : -1.0;
  const bool keep = options.keep_node_gaps;
  if (keep) result.dz_a.assign(static_cast<std::size_t>(a.samples), std::nan(""));
  const double sign = cross > 0.0 ? 1.0 : -1.0;
  // A's columns whose B column is inside B's raster.
  const int64_t c_begin = std::max(a.c_lo, dc), c_end = std::min(a.c_hi + 1, rb.columns + dc);
  const int64_t box_rows = a.BoxRows();
  std::vector<ChunkSums> parts(RowChunks(box_rows));
  std::vector<uint8_t> same_positions(parts.size(), 1);
  ForEachChunk(execution, box_rows, static_cast<int>(parts.size()), [&](int chunk, int64_t begin, int64_t end) {
    ChunkSums& sums = parts[chunk];
    // Rolling rows of completeness: A's rows r − 1 and r, B's likewise.
    std::vector<uint8_t> a_above(ra.columns), a_here(ra.columns), b_above(rb.columns), b_here(rb.columns);
    a.CompleteRow(a.r_lo + begin - 1, a_above.data());
    b.CompleteRow(a.r_lo + begin - 1 - dr, b_above.data());
    for (int64_t r = a.r_lo + begin; r < a.r_lo + end; ++r) {
      if (r > a.r_lo + begin) a_above.swap(a_here), b_above.swap(b_here);
      a.CompleteRow(r, a_here.data());
      const int64_t rb_row = r - dr;
      b.CompleteRow(rb_row, b_here.data());
      if (rb_row < 0 || rb_row >= rb.rows) continue;  // no node or cell of B in this row
      // Nodes: A's sample numbers run over the whole row.
      const double* za = ra.z + r * ra.columns;
      const double* zb = rb.z + rb_row * rb.columns;
      int64_t k = a.row_start[r];
      for (int64_t c = 0; c < c_begin; ++c) k += std::isfinite(za[c]);
      for (int64_t c = c_begin; c < c_end; ++c) {
        if (!std::isfinite(za[c])) continue;
        const int64_t i = k++;
        if (!std::isfinite(zb[c - dc])) continue;
        const Point2 pa = a.Xy(c, r), pb = b.Xy(c - dc, rb_row);
        if (!(pa.x == pb.x && pa.y == pb.y)) same_positions[chunk] = 0;
        if (!DomainVertex(a_above.data(), a_here.data(), c, ra.columns) ||
            !DomainVertex(b_above.data(), b_here.data(), c - dc, rb.columns)) {
          continue;
        }
        const double d = b.Z(c - dc, rb_row) - a.Z(c, r);
        if (keep) result.dz_a[i] = d;
        sums.gap_sum += std::fabs(d);
        sums.node_weight += 1.0;
        ++sums.nodes;
      }
      if (r + 1 >= ra.rows || rb_row + 1 >= rb.rows) continue;
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
          const int k0 = t[0], k1 = sign > 0.0 ? t[1] : t[2], k2 = sign > 0.0 ? t[2] : t[1];
          const Point2 corners[3] = {p[k0], p[k1], p[k2]};
          const double gaps[3] = {d[k0], d[k1], d[k2]};
          IntegrateTriangle(corners, gaps, lod, &sums.volume);
          ++sums.volume.cells;
        }
      }
    }
  });
  if (!std::all_of(same_positions.begin(), same_positions.end(), [](uint8_t s) { return s != 0; })) return false;

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
  if (keep && node_areas) result.node_area_a = NodeAreasOf(execution, a, result.dz_a);

  MeasureSummary summary;
  summary.volume_mode = options.volume;
  summary.n_points_a = a.samples;
  summary.n_points_b = b.samples;
  SetVolumeFields(result.volume,
                  {result.hull_area_a, result.hull_area_b, result.domain_area_a, result.domain_area_b}, options,
                  &summary);
  summary.rho_d_axial = result.rho_d_axial;
  summary.n_overlap_nodes = result.n_overlap_nodes;
  if (keep) {
    summary.dz_a = std::move(result.dz_a);
    summary.node_area_a = std::move(result.node_area_a);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.timings.volume = summary.timings.total = seconds;
  *out = std::move(summary);
  return true;
}

}  // namespace surfreg

#include "io/raster_resample.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/grid_mesh.h"
#include "measure/locator.h"
#include "measure/predicates.h"
#include "measure/tasks.h"

namespace surfreg {
namespace {

// Per input point, its height; points merged as duplicate xy share their
// group's mean, as the measures treat them.
std::vector<double> MergedHeights(const Surface& s, const Triangulation& mesh) {
  if (mesh.num_duplicates == 0) return s.z;
  std::vector<double> sum(s.size(), 0.0);
  std::vector<int> count(s.size(), 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    sum[mesh.vertex_of_input[i]] += s.z[i];
    ++count[mesh.vertex_of_input[i]];
  }
  std::vector<double> z(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const int32_t v = mesh.vertex_of_input[i];
    z[i] = sum[v] / count[v];
  }
  return z;
}

DelaunayOptions On(const Execution& execution) {
  DelaunayOptions options;
  options.execution = execution;
  return options;
}

// The surface's piecewise-linear interpolant on its data domain.
struct Sampler {
  Sampler(const Surface& s, const Execution& execution) : surface(s), mesh(Triangulate(s.xy, On(execution))) {
    DomainRule rule;
    std::vector<uint8_t> in_grid;
    if (s.raster_grid()) {
      rule.grid = true;
      in_grid = EnforceGrid(s.xy, GridCellTriangles(s.raster_cell, s.source, execution), &mesh);
    }
    domain = MakeMeshDomain(s.xy, mesh, rule, rule.grid ? &in_grid : nullptr, execution);
    z = MergedHeights(s, mesh);
  }
  // The height at (x, y) (the surface's input coordinates), NaN outside its
  // data domain; walks from *start (neighbouring queries: cheap walks).
  double At(double x, double y, int32_t* start) const {
    const Point2 p{x - surface.origin[0], y - surface.origin[1]};
    const Location location = LocatePoint(surface.xy, mesh, p, *start);
    if (location.triangle >= 0) *start = location.triangle;
    if (!location.found() || !domain.Contains(mesh, location)) return std::numeric_limits<double>::quiet_NaN();
    return InterpolateAt(mesh, z, location) + surface.origin[2];
  }
  const Surface& surface;
  Triangulation mesh;
  MeshDomain domain;
  std::vector<double> z;
};

// Cells per chunk of the grid's cells: each chunk walks from triangle 0 to
// its first cell, then from cell to neighbouring cell. The chunks depend on
// the grid's size only, so the heights do not depend on the threads.
constexpr int64_t kChunkCells = 1 << 16;

Raster EmptyLike(const Raster& grid_template, const std::string& source, const Execution& execution) {
  Raster out;
  out.columns = grid_template.columns;
  out.rows = grid_template.rows;
  out.geotransform = grid_template.geotransform;
  out.crs_wkt = grid_template.crs_wkt;
  out.source = source;
  // Its pages first touched by the chunks (Raster::values is uninitialized).
  AssignInChunks(execution, static_cast<std::size_t>(out.columns) * out.rows,
                 std::numeric_limits<double>::quiet_NaN(), &out.values);
  return out;
}

// A raster's samples anywhere (moved rigidly, onto another grid): the grid
// mesh is its cells split by the rule (grid_mesh.h), so no Delaunay, no
// forced edges and no walks are needed. Each cell triangle finds the grid's
// cell centres in its box, each decided by exact orientation tests; a
// centre on edges of several triangles goes to the one listed first, so
// the heights do not depend on the order the triangles ran in. False (the
// general path then) if a triangle folds over or is flat, if two triangles
// overlap at a centre, or if the grid is not north-up.
bool ResampleRasterCells(const Surface& s, const Execution& execution, Raster* out) {
  const std::array<double, 6>& gt = out->geotransform;
  if (!s.raster_grid() || gt[2] != 0.0 || gt[4] != 0.0 || !(gt[1] != 0.0 && gt[5] != 0.0)) return false;
  const std::vector<int32_t> corners = GridCellTriangles(s.raster_cell, s.source, execution);
  const int64_t triangles = static_cast<int64_t>(corners.size() / 3);
  if (triangles == 0) return false;  // no complete cell: the mesh's path (and its errors, for < 3 samples)
  // Index-space bounds of a coordinate range along one axis (widened past
  // rounding; the exact tests decide).
  const auto index_range = [](double lo, double hi, double origin, double step, int64_t count, int64_t* first,
                              int64_t* last) {
    double a = (lo - origin) / step - 0.5, b = (hi - origin) / step - 0.5;
    if (a > b) std::swap(a, b);
    constexpr double kWiden = 1e-6;
    *first = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(a - kWiden)));
    *last = std::min<int64_t>(count - 1, static_cast<int64_t>(std::floor(b + kWiden)));
  };
  // The window of the grid the samples' box covers (a large grid under a
  // small surface needs no state per cell outside it).
  Point2 lo = s.xy[0], hi = s.xy[0];
  for (const Point2& p : s.xy) {
    lo.x = std::min(lo.x, p.x), lo.y = std::min(lo.y, p.y);
    hi.x = std::max(hi.x, p.x), hi.y = std::max(hi.y, p.y);
  }
  int64_t window_c0, window_c1, window_r0, window_r1;
  index_range(lo.x + s.origin[0], hi.x + s.origin[0], gt[0], gt[1], out->columns, &window_c0, &window_c1);
  index_range(lo.y + s.origin[1], hi.y + s.origin[1], gt[3], gt[5], out->rows, &window_r0, &window_r1);
  if (window_c0 > window_c1 || window_r0 > window_r1) return true;  // off the grid: all nodata
  const int64_t columns = window_c1 - window_c0 + 1, rows = window_r1 - window_r0 + 1;
  const int64_t cells = columns * rows;
  // Per window cell: 2 t + 1 for triangle t holding its centre on an edge,
  // 2 t strictly inside; the least such code kept (kNone: no triangle).
  constexpr int64_t kNone = std::numeric_limits<int64_t>::max();
  std::unique_ptr<std::atomic<int64_t>[]> owner(new std::atomic<int64_t>[static_cast<std::size_t>(cells)]);
  ForEachChunk(execution, cells, ChunksFor(cells, 1 << 16), [&](int, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) owner[i].store(kNone, std::memory_order_relaxed);
  });
  // The orientation all triangles must share: the first one's.
  const double sign = Orient2D(s.xy[corners[0]], s.xy[corners[1]], s.xy[corners[2]]) > 0.0 ? 1.0 : -1.0;
  std::atomic<bool> general{false};
  // A centre's relative position, as the general path forms it.
  const auto centre = [&](int64_t c, int64_t r) {
    const Point2 p = out->CellCentre(static_cast<int>(c), static_cast<int>(r));
    return Point2{p.x - s.origin[0], p.y - s.origin[1]};
  };
  ForEachChunk(execution, triangles, ChunksFor(triangles, 1 << 15), [&](int, int64_t begin, int64_t end) {
    for (int64_t t = begin; t < end && !general.load(std::memory_order_relaxed); ++t) {
      const Point2& a = s.xy[corners[3 * t]];
      const Point2& b = s.xy[corners[3 * t + 1]];
      const Point2& c = s.xy[corners[3 * t + 2]];
      if (!(Orient2D(a, b, c) * sign > 0.0)) {
        general.store(true, std::memory_order_relaxed);
        return;
      }
      int64_t c_first, c_last, r_first, r_last;
      index_range(std::min({a.x, b.x, c.x}) + s.origin[0], std::max({a.x, b.x, c.x}) + s.origin[0], gt[0], gt[1],
                  out->columns, &c_first, &c_last);
      index_range(std::min({a.y, b.y, c.y}) + s.origin[1], std::max({a.y, b.y, c.y}) + s.origin[1], gt[3], gt[5],
                  out->rows, &r_first, &r_last);
      c_first = std::max(c_first, window_c0), c_last = std::min(c_last, window_c1);
      r_first = std::max(r_first, window_r0), r_last = std::min(r_last, window_r1);
      for (int64_t r = r_first; r <= r_last; ++r) {
        for (int64_t col = c_first; col <= c_last; ++col) {
          const Point2 p = centre(col, r);
          // At a corner (a grid onto itself: every centre), without the
          // exact stage the zero determinants would take.
          bool on_edge = SamePoint(p, a) || SamePoint(p, b) || SamePoint(p, c);
          if (!on_edge) {
            const double o0 = Orient2D(b, c, p) * sign;
            if (o0 < 0.0) continue;
            const double o1 = Orient2D(c, a, p) * sign;
            if (o1 < 0.0) continue;
            const double o2 = Orient2D(a, b, p) * sign;
            if (o2 < 0.0) continue;
            on_edge = o0 == 0.0 || o1 == 0.0 || o2 == 0.0;
          }
          const int64_t code = 2 * t + (on_edge ? 1 : 0);
          std::atomic<int64_t>& slot = owner[(r - window_r0) * columns + (col - window_c0)];
          int64_t seen = slot.load(std::memory_order_relaxed);
          for (;;) {
            // Inside one triangle and in another's closure: they overlap.
            if (seen != kNone && (!on_edge || seen % 2 == 0)) {
              general.store(true, std::memory_order_relaxed);
              return;
            }
            if (code >= seen || slot.compare_exchange_weak(seen, code, std::memory_order_relaxed)) break;
          }
        }
      }
    }
  });
  if (general.load()) return false;
  // Each centre's height from its triangle, as LocatePoint's barycentric
  // coordinates give it (exact zeros on the edges that hold it).
  ForEachChunk(execution, cells, ChunksFor(cells, 1 << 16), [&](int, int64_t begin, int64_t end) {
    for (int64_t k = begin; k < end; ++k) {
      const int64_t code = owner[k].load(std::memory_order_relaxed);
      if (code == kNone) continue;
      const int32_t* v = &corners[3 * (code / 2)];
      const int64_t col = window_c0 + k % columns, r = window_r0 + k / columns;
      const int64_t i = r * out->columns + col;
      const Point2 p = centre(col, r);
      const Point2& a = s.xy[v[0]];
      const Point2& b = s.xy[v[1]];
      const Point2& c = s.xy[v[2]];
      const int corner = SamePoint(p, a) ? 0 : SamePoint(p, b) ? 1 : SamePoint(p, c) ? 2 : -1;
      if (corner >= 0) {  // barycentric (1, 0, 0) in some order: that corner's height
        out->values[i] = s.z[v[corner]] + s.origin[2];
        continue;
      }
      double w[3] = {Orient2DAccurate(b, c, p) * sign, Orient2DAccurate(c, a, p) * sign,
                     Orient2DAccurate(a, b, p) * sign};
      for (double& x : w) x = std::max(x, 0.0);
      const double sum = w[0] + w[1] + w[2];
      out->values[i] =
          (w[0] / sum) * s.z[v[0]] + (w[1] / sum) * s.z[v[1]] + (w[2] / sum) * s.z[v[2]] + s.origin[2];
    }
  });
  return true;
}

}  // namespace

Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template, const Execution& execution) {
  Raster out = EmptyLike(grid_template, moved.source, execution);
  if (ResampleRasterCells(moved, execution, &out)) return out;
  const Sampler sampler(moved, execution);
  // Row-major cells are neighbours: each walk starts where the last ended.
  const int64_t n = static_cast<int64_t>(out.values.size());
  ForEachChunk(execution, n, ChunksFor(n, kChunkCells), [&](int, int64_t begin, int64_t end) {
    int32_t start = 0;
    for (int64_t i = begin; i < end; ++i) {
      const Point2 centre = out.CellCentre(static_cast<int>(i % out.columns), static_cast<int>(i / out.columns));
      out.values[i] = sampler.At(centre.x, centre.y, &start);
    }
  });
  return out;
}

Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template, const GridToSurface& to_surface,
                        const Execution& execution) {
  const Sampler sampler(moved, execution);
  Raster out = EmptyLike(grid_template, moved.source, execution);
  const std::size_t n = out.values.size();
  std::vector<double> h(n, 0.0);
  std::vector<uint8_t> live(n, 1);
  std::vector<std::array<double, 3>> points(n);
  for (int pass = 0; pass < 4; ++pass) {
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 centre = out.CellCentre(static_cast<int>(i % out.columns), static_cast<int>(i / out.columns));
      points[i] = {centre.x, centre.y, h[i]};
    }
    to_surface(&points);
    const int chunks = ChunksFor(static_cast<int64_t>(n), kChunkCells);
    std::vector<uint8_t> moved_in(chunks, 0);
    ForEachChunk(execution, static_cast<int64_t>(n), chunks, [&](int c, int64_t begin, int64_t end) {
      int32_t start = 0;
      for (int64_t i = begin; i < end; ++i) {
        if (!live[i]) continue;
        const double z = sampler.At(points[i][0], points[i][1], &start);
        if (!std::isfinite(z)) {
          live[i] = 0;  // outside the data domain: nodata
          continue;
        }
        const double step = z - points[i][2];
        h[i] += step;
        if (std::fabs(step) > 1e-9 * (1 + std::fabs(h[i]))) moved_in[c] = 1;
      }
    });
    if (std::find(moved_in.begin(), moved_in.end(), 1) == moved_in.end()) break;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (live[i]) out.values[i] = h[i];
  }
  return out;
}

bool IsGeoTiffPath(const std::string& path) {
  std::string extension = path.substr(std::min(path.size(), path.find_last_of('.')));
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".tif" || extension == ".tiff";
}

}  // namespace surfreg

#include "io/raster_resample.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/grid_mesh.h"
#include "measure/locator.h"
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
      in_grid = EnforceGrid(s.xy, GridCellTriangles(s.raster_cell, s.source), &mesh);
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

Raster EmptyLike(const Raster& grid_template, const std::string& source) {
  Raster out;
  out.columns = grid_template.columns;
  out.rows = grid_template.rows;
  out.geotransform = grid_template.geotransform;
  out.crs_wkt = grid_template.crs_wkt;
  out.source = source;
  out.values.assign(static_cast<std::size_t>(out.columns) * out.rows,
                    std::numeric_limits<double>::quiet_NaN());
  return out;
}

}  // namespace

Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template, const Execution& execution) {
  const Sampler sampler(moved, execution);
  Raster out = EmptyLike(grid_template, moved.source);
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
  Raster out = EmptyLike(grid_template, moved.source);
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

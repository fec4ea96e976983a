#include "tools/io/raster_resample.h"

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

}  // namespace

Raster ResampleOntoGrid(const Surface& moved, const Raster& grid_template) {
  Triangulation mesh = Triangulate(moved.xy);
  DomainRule rule;
  std::vector<uint8_t> in_grid;
  if (moved.raster_grid()) {
    rule.grid = true;
    in_grid = EnforceGrid(moved.xy, GridCellTriangles(moved.raster_cell, moved.source), &mesh);
  }
  const MeshDomain domain = MakeMeshDomain(moved.xy, mesh, rule, rule.grid ? &in_grid : nullptr);
  const std::vector<double> z = MergedHeights(moved, mesh);

  Raster out;
  out.columns = grid_template.columns;
  out.rows = grid_template.rows;
  out.geotransform = grid_template.geotransform;
  out.crs_wkt = grid_template.crs_wkt;
  out.source = moved.source;
  out.values.assign(static_cast<std::size_t>(out.columns) * out.rows,
                    std::numeric_limits<double>::quiet_NaN());
  // Row-major cells are neighbours: each walk starts where the last ended.
  int32_t start = 0;
  for (int row = 0; row < out.rows; ++row) {
    for (int column = 0; column < out.columns; ++column) {
      const Point2 centre = out.CellCentre(column, row);
      const Point2 p{centre.x - moved.origin[0], centre.y - moved.origin[1]};
      const Location location = LocatePoint(moved.xy, mesh, p, start);
      if (location.triangle >= 0) start = location.triangle;
      if (!location.found() || !domain.Contains(mesh, location)) continue;
      out.values[static_cast<std::size_t>(row) * out.columns + column] =
          InterpolateAt(mesh, z, location) + moved.origin[2];
    }
  }
  return out;
}

bool IsGeoTiffPath(const std::string& path) {
  std::string extension = path.substr(std::min(path.size(), path.find_last_of('.')));
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".tif" || extension == ".tiff";
}

}  // namespace surfreg

#pragma once
// Internal to the faces library (symmetry.cc, asymmetry_index.cc): a face or
// its mirror as a Delaunay mesh with one height per vertex, duplicates
// averaged as Measure does, and its interpolant at a point within the data
// domain (measure/domain.h, as Measure uses it: not the hull's slivers, whose
// heights are invented). Not installed.
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/locator.h"

namespace surfreg {
namespace faces_internal {

struct HeightMesh {
  std::vector<Point2> xy;
  std::vector<double> z;  // per vertex (a merged duplicate's is its survivor's average)
  Triangulation mesh;
  std::vector<uint8_t> domain;  // per triangle: 1 in the data domain
};

inline HeightMesh MakeHeightMesh(std::vector<Point2> xy, const std::vector<double>& z) {
  HeightMesh out;
  out.mesh = Triangulate(xy);
  out.xy = std::move(xy);
  std::vector<double> sum(z.size(), 0.0);
  std::vector<int> count(z.size(), 0);
  for (std::size_t i = 0; i < z.size(); ++i) {
    sum[out.mesh.vertex_of_input[i]] += z[i];
    ++count[out.mesh.vertex_of_input[i]];
  }
  out.z.assign(z.size(), 0.0);
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (count[i] > 0) out.z[i] = sum[i] / count[i];
  }
  out.domain = DataDomain(out.xy, out.mesh);
  return out;
}

// p's location in the mesh, not found outside the data domain; `start`
// carries the walk from one call to the next.
inline Location LocateHeight(const HeightMesh& m, const Point2& p, int32_t* start) {
  Location location = LocatePoint(m.xy, m.mesh, p, *start);
  if (location.triangle >= 0) *start = location.triangle;
  if (location.found() && m.domain[location.triangle] == 0) location.where = Where::kOutside;
  return location;
}

// Interpolated height at p, or NaN outside.
inline double HeightAt(const HeightMesh& m, const Point2& p, int32_t* start) {
  const Location location = LocateHeight(m, p, start);
  if (!location.found()) return std::numeric_limits<double>::quiet_NaN();
  return InterpolateAt(m.mesh, m.z, location);
}

}  // namespace faces_internal
}  // namespace surfreg

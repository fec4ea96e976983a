#include "registration/kept_remesh.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "measure/enforce_triangles.h"
#include "measure/input_error.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

uint64_t EdgeKey(int32_t a, int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

// A boundary edge of R: the kept triangle's slot (3 t + i, t in the output)
// and the edge's first vertex in that triangle's counter-clockwise order.
struct BoundarySide {
  int32_t slot;
  int32_t from;
};

double TriangleArea(const std::vector<Point2>& p, const int32_t* v) {
  return 0.5 * Orient2D(p[v[0]], p[v[1]], p[v[2]]);
}

// The Delaunay triangulation of the vertices of `triangles`, indexed like
// `points` (the other points belong to no triangle).
Triangulation TriangulateSubset(const std::vector<Point2>& points, const std::vector<int32_t>& triangles) {
  std::vector<int32_t> used(triangles);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<Point2> subset(used.size());
  for (std::size_t k = 0; k < used.size(); ++k) subset[k] = points[used[k]];
  Triangulation mesh = Triangulate(subset);
  for (int32_t& v : mesh.triangles) v = used[v];
  std::vector<int32_t> vertex_triangle(points.size(), -1);
  for (std::size_t k = 0; k < used.size(); ++k) vertex_triangle[used[k]] = mesh.vertex_triangle[k];
  mesh.vertex_triangle = std::move(vertex_triangle);
  mesh.vertex_of_input.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) mesh.vertex_of_input[i] = static_cast<int32_t>(i);
  mesh.num_duplicates = 0;
  return mesh;
}

}  // namespace

bool RemeshAroundKept(const std::vector<Point2>& points, const Triangulation& current,
                      const std::vector<uint8_t>& keep, Triangulation* out) {
  const int32_t num_current = current.num_triangles();
  const std::size_t n = points.size();
  const std::vector<int32_t>& tri = current.triangles;
  std::vector<int32_t> new_index(num_current, -1);
  int32_t num_kept = 0;
  for (int32_t t = 0; t < num_current; ++t) {
    if (!keep[t]) continue;
    const int32_t* v = &tri[3 * t];
    if (!(Orient2D(points[v[0]], points[v[1]], points[v[2]]) > 0.0)) return false;
    new_index[t] = num_kept++;
  }
  if (num_kept == 0) return false;

  // R's boundary: kept triangles' edges without a kept triangle beyond.
  std::vector<uint8_t> on_boundary(n, 0);
  std::unordered_map<uint64_t, BoundarySide> boundary;
  for (int32_t t = 0; t < num_current; ++t) {
    if (!keep[t]) continue;
    for (int i = 0; i < 3; ++i) {
      const int32_t beyond = current.neighbors[3 * t + i];
      if (beyond >= 0 && keep[beyond]) continue;
      const int32_t a = tri[3 * t + (i + 1) % 3], b = tri[3 * t + (i + 2) % 3];
      on_boundary[a] = on_boundary[b] = 1;
      boundary.emplace(EdgeKey(a, b), BoundarySide{3 * new_index[t] + i, a});
    }
  }

  // The ring (kept triangles with a corner on the boundary) and its
  // vertices, which alone are triangulated.
  std::vector<int32_t> local(n, -1), global;
  std::vector<int32_t> required;
  for (int32_t t = 0; t < num_current; ++t) {
    if (!keep[t]) continue;
    const int32_t* v = &tri[3 * t];
    if (!on_boundary[v[0]] && !on_boundary[v[1]] && !on_boundary[v[2]]) continue;
    for (int k = 0; k < 3; ++k) {
      if (local[v[k]] < 0) local[v[k]] = static_cast<int32_t>(global.size()), global.push_back(v[k]);
      required.push_back(local[v[k]]);
    }
  }
  std::vector<Point2> ring_points(global.size());
  for (std::size_t k = 0; k < global.size(); ++k) ring_points[k] = points[global[k]];
  Triangulation ring;
  try {
    ring = Triangulate(ring_points);
  } catch (const InputError&) {
    return false;  // fewer than 3 points, or all on a line
  }
  if (ring.num_duplicates > 0 || !EnforceTriangles(ring_points, required, &ring)) return false;

  // Which of the ring mesh's triangles lie in R: those on a boundary edge's
  // kept side, and all reached from them without crossing the boundary.
  const int32_t num_ring = ring.num_triangles();
  auto edge_of = [&](int32_t s, int j) {
    return std::make_pair(global[ring.triangles[3 * s + (j + 1) % 3]], global[ring.triangles[3 * s + (j + 2) % 3]]);
  };
  std::vector<uint8_t> inside(num_ring, 0);
  std::vector<int32_t> stack;
  for (int32_t s = 0; s < num_ring; ++s) {
    for (int j = 0; j < 3 && !inside[s]; ++j) {
      const auto [a, b] = edge_of(s, j);
      const auto found = boundary.find(EdgeKey(a, b));
      if (found != boundary.end() && found->second.from == a) inside[s] = 1, stack.push_back(s);
    }
  }
  while (!stack.empty()) {
    const int32_t s = stack.back();
    stack.pop_back();
    for (int j = 0; j < 3; ++j) {
      const int32_t next = ring.neighbors[3 * s + j];
      if (next < 0 || inside[next]) continue;
      const auto [a, b] = edge_of(s, j);
      if (boundary.count(EdgeKey(a, b)) != 0) continue;
      inside[next] = 1;
      stack.push_back(next);
    }
  }
  std::vector<int32_t> filler_index(num_ring, -1);
  int32_t num_out = num_kept;
  for (int32_t s = 0; s < num_ring; ++s) {
    if (!inside[s]) filler_index[s] = num_out++;
  }

  // Kept triangles first (their adjacency as in `current`), then the filler.
  Triangulation& mesh = *out;
  mesh.triangles.assign(3 * static_cast<std::size_t>(num_out), -1);
  mesh.neighbors.assign(3 * static_cast<std::size_t>(num_out), -1);
  for (int32_t t = 0; t < num_current; ++t) {
    if (!keep[t]) continue;
    const int32_t u = new_index[t];
    for (int i = 0; i < 3; ++i) {
      mesh.triangles[3 * u + i] = tri[3 * t + i];
      const int32_t beyond = current.neighbors[3 * t + i];
      if (beyond >= 0 && keep[beyond]) mesh.neighbors[3 * u + i] = new_index[beyond];
    }
  }
  for (int32_t s = 0; s < num_ring; ++s) {
    const int32_t u = filler_index[s];
    if (u < 0) continue;
    for (int j = 0; j < 3; ++j) {
      mesh.triangles[3 * u + j] = global[ring.triangles[3 * s + j]];
      const int32_t next = ring.neighbors[3 * s + j];
      if (next < 0) continue;
      if (filler_index[next] >= 0) {
        mesh.neighbors[3 * u + j] = filler_index[next];
        continue;
      }
      const auto [a, b] = edge_of(s, j);
      const auto found = boundary.find(EdgeKey(a, b));
      if (found == boundary.end()) return false;  // cannot be: only the boundary separates them
      mesh.neighbors[3 * u + j] = found->second.slot / 3;
      mesh.neighbors[found->second.slot] = u;
    }
  }
  // The pieces tile the ring mesh's hull, which is the kept vertices' hull,
  // unless kept triangles overlap (a safety net: such overlaps cross the
  // ring, where EnforceTriangles refuses them).
  double area = 0;
  for (int32_t u = 0; u < num_out; ++u) area += TriangleArea(points, &mesh.triangles[3 * u]);
  const double hull_area = MeshArea(ring_points, ring);
  if (!(std::fabs(area - hull_area) <= 1e-9 * hull_area)) return false;

  mesh.vertex_triangle.assign(n, -1);
  for (int32_t u = 0; u < num_out; ++u) {
    for (int k = 0; k < 3; ++k) mesh.vertex_triangle[mesh.triangles[3 * u + k]] = u;
  }
  mesh.vertex_of_input.resize(n);
  for (std::size_t i = 0; i < n; ++i) mesh.vertex_of_input[i] = static_cast<int32_t>(i);
  mesh.num_duplicates = 0;
  return true;
}

bool TriangulateKept(const std::vector<Point2>& points, const std::vector<int32_t>& triangles,
                     Triangulation* out) {
  *out = TriangulateSubset(points, triangles);
  return EnforceTriangles(points, triangles, out);
}

}  // namespace surfreg

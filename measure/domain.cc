#include "measure/domain.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "measure/locator.h"

namespace surfreg {
namespace {

// Not std::hypot: coordinates are in a local frame, far from overflow, and
// hypot's care was 2.4% of a face alignment's time.
double Length(const Point2& a, const Point2& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  return std::sqrt(dx * dx + dy * dy);
}

// The longest edge of a triangle, named by its opposite local vertex (0-2).
int LongestEdge(const std::vector<Point2>& xy, const int32_t* v, double* length) {
  int best = 0;
  *length = -1;
  for (int i = 0; i < 3; ++i) {
    const double l = Length(xy[v[(i + 1) % 3]], xy[v[(i + 2) % 3]]);
    if (l > *length) *length = l, best = i;
  }
  return best;
}

// Each vertex's local sample spacing: the median length of its Delaunay edges
// (every interior edge is seen from both triangles, hull edges once), then
// the lower quartile of that over its neighbours (the vertex following it in
// each of its triangles). A vertex's triangles are listed once (flat
// arrays); then each vertex's order statistics are its own, in chunks of
// vertices, with one buffer per chunk: no allocation per vertex (this runs
// in every Measure), and the same values on any number of threads (a k-th
// smallest does not depend on the order its values come in).
std::vector<double> LocalSpacing(const std::vector<Point2>& xy, const Triangulation& mesh,
                                 const Execution& execution) {
  const std::size_t n = xy.size();
  const int32_t num_triangles = mesh.num_triangles();
  std::vector<int32_t> first(n + 1, 0);  // a vertex's triangles: around[first[v] .. first[v + 1])
  for (int32_t t = 0; t < num_triangles; ++t) {
    for (int i = 0; i < 3; ++i) ++first[mesh.triangles[3 * t + i] + 1];
  }
  for (std::size_t v = 0; v < n; ++v) first[v + 1] += first[v];
  // Each entry: 3 t + the vertex's corner in triangle t.
  std::vector<int32_t> around(static_cast<std::size_t>(first[n]));
  {
    std::vector<int32_t> next(first.begin(), first.end() - 1);
    for (int32_t t = 0; t < num_triangles; ++t) {
      for (int i = 0; i < 3; ++i) around[next[mesh.triangles[3 * t + i]]++] = 3 * t + i;
    }
  }
  const int64_t vertices = static_cast<int64_t>(n);
  const int chunks = ChunksFor(vertices, 4096);
  std::vector<double> spacing(n, 0.0);
  ForEachChunk(execution, vertices, chunks, [&](int, int64_t begin, int64_t end) {
    std::vector<float> lengths;
    for (int64_t v = begin; v < end; ++v) {
      lengths.clear();
      for (int32_t k = first[v]; k < first[v + 1]; ++k) {  // the two edges at v in each triangle
        const int32_t t = around[k] / 3, i = around[k] % 3;
        const Point2& p = xy[v];
        lengths.push_back(static_cast<float>(Length(p, xy[mesh.triangles[3 * t + (i + 1) % 3]])));
        lengths.push_back(static_cast<float>(Length(p, xy[mesh.triangles[3 * t + (i + 2) % 3]])));
      }
      if (lengths.empty()) continue;
      std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
      spacing[v] = lengths[lengths.size() / 2];
    }
  });
  std::vector<double> local(n, 0.0);
  ForEachChunk(execution, vertices, chunks, [&](int, int64_t begin, int64_t end) {
    std::vector<float> ring;
    for (int64_t v = begin; v < end; ++v) {
      ring.clear();
      for (int32_t k = first[v]; k < first[v + 1]; ++k) {
        const int32_t t = around[k] / 3, i = around[k] % 3;
        ring.push_back(static_cast<float>(spacing[mesh.triangles[3 * t + (i + 1) % 3]]));
      }
      if (ring.empty()) continue;
      std::nth_element(ring.begin(), ring.begin() + ring.size() / 4, ring.end());
      local[v] = ring[ring.size() / 4];
    }
  });
  return local;
}

}  // namespace

std::vector<uint8_t> DataDomain(const std::vector<Point2>& xy, const Triangulation& mesh,
                                const DomainRule& rule, const std::vector<uint8_t>* grid,
                                const Execution& execution) {
  const int32_t n = mesh.num_triangles();
  if (rule.kind == DomainKind::kHull) return std::vector<uint8_t>(n, 1);
  if (rule.grid) {
    if (grid == nullptr || grid->size() != static_cast<std::size_t>(n)) {
      throw std::invalid_argument("DataDomain: a raster's domain needs its grid triangles");
    }
    return *grid;
  }
  std::vector<uint8_t> in(n, 1);
  const std::vector<double> spacing = LocalSpacing(xy, mesh, execution);
  std::vector<double> thinness(n);
  ForEachChunk(execution, n, ChunksFor(n, 8192), [&](int, int64_t begin, int64_t end) {
    for (int64_t t = begin; t < end; ++t) {
      const int32_t* v = &mesh.triangles[3 * t];
      double longest = 0;
      LongestEdge(xy, v, &longest);
      const double local = std::max({spacing[v[0]], spacing[v[1]], spacing[v[2]]});
      if (longest > rule.max_edge_spacings * local) in[t] = 0;
      thinness[t] = longest > 0 ? std::fabs(TwiceArea(xy[v[0]], xy[v[1]], xy[v[2]])) / (longest * longest) : 0.0;
    }
  });
  // Peel boundary slivers from the outside in: a triangle is on the boundary
  // when a neighbour is missing or out of the domain.
  auto on_boundary = [&](int32_t t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t u = mesh.neighbors[3 * t + i];
      if (u < 0 || !in[u]) return true;
    }
    return false;
  };
  std::vector<int32_t> queue;
  for (int32_t t = 0; t < n; ++t) {
    if (in[t] && thinness[t] < rule.min_boundary_thinness && on_boundary(t)) queue.push_back(t);
  }
  while (!queue.empty()) {
    const int32_t t = queue.back();
    queue.pop_back();
    if (!in[t]) continue;
    in[t] = 0;
    for (int i = 0; i < 3; ++i) {
      const int32_t u = mesh.neighbors[3 * t + i];
      if (u >= 0 && in[u] && thinness[u] < rule.min_boundary_thinness) queue.push_back(u);
    }
  }
  return in;
}

double DomainArea(const std::vector<Point2>& xy, const Triangulation& mesh,
                  const std::vector<uint8_t>& in_domain) {
  double twice = 0;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!in_domain[t]) continue;
    const int32_t* v = &mesh.triangles[3 * t];
    twice += TwiceArea(xy[v[0]], xy[v[1]], xy[v[2]]);
  }
  return 0.5 * twice;
}

std::vector<uint8_t> DomainVertices(const Triangulation& mesh, std::size_t num_vertices,
                                    const std::vector<uint8_t>& in_domain) {
  std::vector<uint8_t> used(num_vertices, 0);
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!in_domain[t]) continue;
    for (int i = 0; i < 3; ++i) used[mesh.triangles[3 * t + i]] = 1;
  }
  return used;
}

std::vector<uint8_t> InteriorVertices(const Triangulation& mesh, std::size_t num_vertices,
                                      const std::vector<uint8_t>& in_domain) {
  std::vector<uint8_t> inner = DomainVertices(mesh, num_vertices, in_domain);
  // Around a vertex, a change from a domain triangle to anything else
  // crosses an edge at that vertex: zeroing both ends of every outline edge
  // zeroes every vertex that touches the outside.
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (!in_domain[t]) continue;
    for (int i = 0; i < 3; ++i) {
      const int32_t next = mesh.neighbors[3 * t + i];
      if (next >= 0 && in_domain[next]) continue;
      inner[mesh.triangles[3 * t + (i + 1) % 3]] = 0;
      inner[mesh.triangles[3 * t + (i + 2) % 3]] = 0;
    }
  }
  return inner;
}

const char* DomainKindName(DomainKind kind) {
  return kind == DomainKind::kHull ? "hull" : "data";
}

bool MeshDomain::Contains(const Triangulation& mesh, const Location& location) const {
  switch (location.where) {
    case Where::kOutside:
      return false;
    case Where::kInside:
      return whole || triangles[location.triangle];
    case Where::kOnEdge: {
      const int32_t across = mesh.neighbors[3 * location.triangle + location.index];
      return whole || triangles[location.triangle] || (across >= 0 && triangles[across]);
    }
    case Where::kOnVertex:
      return whole || vertices[mesh.triangles[3 * location.triangle + location.index]];
  }
  return false;
}

MeshDomain MakeMeshDomain(const std::vector<Point2>& xy, const Triangulation& mesh,
                          const DomainRule& rule, const std::vector<uint8_t>* grid, const Execution& execution) {
  MeshDomain domain;
  domain.triangles = DataDomain(xy, mesh, rule, grid, execution);
  domain.vertices = DomainVertices(mesh, xy.size(), domain.triangles);
  domain.area = DomainArea(xy, mesh, domain.triangles);
  domain.whole = std::all_of(domain.triangles.begin(), domain.triangles.end(),
                             [](uint8_t in) { return in != 0; });
  return domain;
}

}  // namespace surfreg

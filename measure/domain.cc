#include "measure/domain.h"

#include <algorithm>
#include <cmath>

namespace surfreg {
namespace {

double Length(const Point2& a, const Point2& b) { return std::hypot(b.x - a.x, b.y - a.y); }

double TwiceArea(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
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
// the lower quartile of that over its neighbours.
std::vector<double> LocalSpacing(const std::vector<Point2>& xy, const Triangulation& mesh) {
  std::vector<std::vector<float>> lengths(xy.size());
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    for (int i = 0; i < 3; ++i) {
      const int32_t a = v[i], b = v[(i + 1) % 3];
      const float l = static_cast<float>(Length(xy[a], xy[b]));
      lengths[a].push_back(l);
      lengths[b].push_back(l);
    }
  }
  std::vector<double> spacing(xy.size(), 0.0);
  for (std::size_t k = 0; k < xy.size(); ++k) {
    std::vector<float>& l = lengths[k];
    if (l.empty()) continue;
    std::nth_element(l.begin(), l.begin() + l.size() / 2, l.end());
    spacing[k] = l[l.size() / 2];
  }
  // The lower quartile over the neighbours' medians: a vertex on a void's
  // rim has long edges across it (its own median is inflated), but interior
  // neighbours too; along scan lines every vertex's median is the distance
  // between lines, as it should be (the lower quartile of a vertex's own
  // edges would be the spacing along them, and leave 70% of a scan out).
  std::vector<std::vector<float>> ring(xy.size());
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    for (int i = 0; i < 3; ++i) ring[v[i]].push_back(static_cast<float>(spacing[v[(i + 1) % 3]]));
  }
  std::vector<double> local(xy.size(), 0.0);
  for (std::size_t k = 0; k < xy.size(); ++k) {
    std::vector<float>& r = ring[k];
    if (r.empty()) continue;
    std::nth_element(r.begin(), r.begin() + r.size() / 4, r.end());
    local[k] = r[r.size() / 4];
  }
  return local;
}

std::vector<uint8_t> GridDomain(const std::vector<Point2>& xy, const Triangulation& mesh) {
  const int32_t n = mesh.num_triangles();
  std::vector<uint8_t> in(n, 0);
  for (int32_t t = 0; t < n; ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    double longest = 0;
    const int i = LongestEdge(xy, v, &longest);
    const int32_t u = mesh.neighbors[3 * t + i];
    if (u < 0) continue;
    const int32_t* w = &mesh.triangles[3 * u];
    int32_t opposite = -1;
    for (int j = 0; j < 3; ++j) {
      if (w[j] != v[(i + 1) % 3] && w[j] != v[(i + 2) % 3]) opposite = w[j];
    }
    // The cell's fourth corner is where the parallelogram on the right
    // angle's corner and the diagonal puts it; projected rasters are lattices
    // up to rounding, reprojected ones deviate by far less than 1% of a cell.
    const Point2& a = xy[v[(i + 1) % 3]];
    const Point2& b = xy[v[(i + 2) % 3]];
    const Point2& c = xy[v[i]];
    const Point2 expected = {a.x + b.x - c.x, a.y + b.y - c.y};
    in[t] = Length(xy[opposite], expected) <= 0.01 * longest;
  }
  return in;
}

}  // namespace

std::vector<uint8_t> DataDomain(const std::vector<Point2>& xy, const Triangulation& mesh,
                                const DomainRule& rule) {
  const int32_t n = mesh.num_triangles();
  if (rule.kind == DomainKind::kHull) return std::vector<uint8_t>(n, 1);
  if (rule.grid) return GridDomain(xy, mesh);
  std::vector<uint8_t> in(n, 1);
  const std::vector<double> spacing = LocalSpacing(xy, mesh);
  std::vector<double> thinness(n);
  for (int32_t t = 0; t < n; ++t) {
    const int32_t* v = &mesh.triangles[3 * t];
    double longest = 0;
    LongestEdge(xy, v, &longest);
    const double local = std::max({spacing[v[0]], spacing[v[1]], spacing[v[2]]});
    if (longest > rule.max_edge_spacings * local) in[t] = 0;
    thinness[t] = longest > 0 ? std::fabs(TwiceArea(xy[v[0]], xy[v[1]], xy[v[2]])) /
                                    (longest * longest)
                              : 0.0;
  }
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

const char* DomainKindName(DomainKind kind) {
  return kind == DomainKind::kHull ? "hull" : "data";
}

}  // namespace surfreg

#include "measure/delaunay.h"

#include <algorithm>
#include <limits>

#include "measure/delaunay_internal.h"
#include "measure/input_error.h"
#include "measure/predicates.h"
#include "measure/spatial_sort.h"

namespace surfreg {
namespace {

// Incremental Bowyer-Watson construction with "ghost" triangles: every
// convex-hull edge a->b has a ghost triangle (b, a, kInfinite) outside it, so
// points outside the hull are inserted exactly like points inside.
//
// Edge i of triangle t is opposite its vertex i, from vertex i+1 to vertex
// i+2 (mod 3). twin_[3t + i] names the same edge seen from the neighbouring
// triangle u as the half-edge 4u + j (shifts, not divisions, to decode).
// Vertices are positions in the insertion order.
constexpr int32_t kInfinite = -1;

inline int Next(int i) { return i == 2 ? 0 : i + 1; }
inline int Prev(int i) { return i == 0 ? 2 : i - 1; }
inline int32_t HalfEdge(int32_t t, int i) { return 4 * t + i; }
inline int32_t TriangleOf(int32_t h) { return h >> 2; }
inline int EdgeOf(int32_t h) { return h & 3; }

struct CavityEdge {
  int32_t from, to;  // counter-clockwise around the cavity
  int32_t outer;     // half-edge of the surviving triangle across it
};

class Builder {
 public:
  explicit Builder(std::vector<Point2> points) : p_(std::move(points)) {
    // With the infinite vertex, k vertices make 2k - 2 triangles at any
    // time: the arrays never grow (no reallocation, no resize per triangle).
    const std::size_t capacity = 3 * (2 * p_.size() + 2);
    vertex_.resize(capacity);
    twin_.resize(capacity);
    duplicate_of_.assign(p_.size(), -1);
  }

  // Builds the first triangle from vertices a, b, c (counter-clockwise).
  void Start(int32_t a, int32_t b, int32_t c) {
    AddTriangle(a, b, c);                 // t0
    AddTriangle(c, b, kInfinite);         // t1, outside edge b->c
    AddTriangle(a, c, kInfinite);         // t2, outside edge c->a
    AddTriangle(b, a, kInfinite);         // t3, outside edge a->b
    Link(HalfEdge(0, 0), HalfEdge(1, 2));  // b->c and c->b
    Link(HalfEdge(0, 1), HalfEdge(2, 2));  // c->a and a->c
    Link(HalfEdge(0, 2), HalfEdge(3, 2));  // a->b and b->a
    // Ghost-to-ghost edges around the infinite vertex.
    Link(HalfEdge(1, 0), HalfEdge(3, 1));  // b->inf, inf->b
    Link(HalfEdge(1, 1), HalfEdge(2, 0));  // inf->c, c->inf
    Link(HalfEdge(2, 1), HalfEdge(3, 0));  // inf->a, a->inf
    last_finite_ = 0;
  }

  // Inserts vertex v; returns false if it duplicates an existing vertex.
  bool Insert(int32_t v) {
    const Point2& p = p_[v];
    const int32_t t = Locate(p);
    if (!IsGhost(t)) {
      for (int i = 0; i < 3; ++i) {
        const int32_t w = vertex_[3 * t + i];
        if (p_[w].x == p.x && p_[w].y == p.y) {
          duplicate_of_[v] = w;
          return false;
        }
      }
    }
    DigCavity(t, p);
    FillCavity(v);
    return true;
  }

  int32_t num_slots() const { return num_slots_; }
  const std::vector<int32_t>& vertex() const { return vertex_; }
  const std::vector<int32_t>& twin() const { return twin_; }
  const std::vector<int32_t>& duplicate_of() const { return duplicate_of_; }
  bool IsGhost(int32_t t) const {
    return vertex_[3 * t] == kInfinite || vertex_[3 * t + 1] == kInfinite ||
           vertex_[3 * t + 2] == kInfinite;
  }

 private:
  int32_t AddTriangle(int32_t a, int32_t b, int32_t c) {
    const int32_t t = num_slots_++;
    SetTriangle(t, a, b, c);
    return t;
  }
  void SetTriangle(int32_t t, int32_t a, int32_t b, int32_t c) {
    vertex_[3 * t] = a;
    vertex_[3 * t + 1] = b;
    vertex_[3 * t + 2] = c;
  }
  void Link(int32_t h, int32_t g) {
    twin_[3 * TriangleOf(h) + EdgeOf(h)] = g;
    twin_[3 * TriangleOf(g) + EdgeOf(g)] = h;
  }

  // Visibility walk from the last finite triangle: step across any edge that
  // has p strictly on its outer side. On a Delaunay triangulation this walk
  // cannot cycle. Returns a finite triangle whose closure holds p, or the
  // ghost triangle beyond the hull edge through which p was left.
  int32_t Locate(const Point2& p) const {
    int32_t t = last_finite_;
    int entry = 0;  // edge we came in by; not tested again
    bool first = true;
    for (;;) {
      int i = first ? 0 : Next(entry);
      bool moved = false;
      for (int k = first ? 0 : 1; k < 3; ++k, i = Next(i)) {
        const int32_t a = vertex_[3 * t + Next(i)];
        const int32_t b = vertex_[3 * t + Prev(i)];
        if (Orient2D(p_[a], p_[b], p) < 0.0) {
          const int32_t h = twin_[3 * t + i];
          t = TriangleOf(h);
          entry = EdgeOf(h);
          moved = true;
          break;
        }
      }
      first = false;
      if (!moved || IsGhost(t)) return t;
    }
  }

  bool InConflict(int32_t t, const Point2& p) const {
    const int32_t* v = &vertex_[3 * t];
    if (v[0] != kInfinite && v[1] != kInfinite && v[2] != kInfinite) {
      return InCirclePerturbed(p_[v[0]], p_[v[1]], p_[v[2]], p) > 0;
    }
    // Ghost: the finite edge x->y has the outside on its left. It conflicts
    // with points strictly outside, and with points inside the edge itself.
    const int inf = v[0] == kInfinite ? 0 : (v[1] == kInfinite ? 1 : 2);
    const Point2& x = p_[v[Next(inf)]];
    const Point2& y = p_[v[Prev(inf)]];
    const double o = Orient2D(x, y, p);
    if (o != 0.0) return o > 0.0;
    if (x.x != y.x) return (x.x < p.x && p.x < y.x) || (y.x < p.x && p.x < x.x);
    return (x.y < p.y && p.y < y.y) || (y.y < p.y && p.y < x.y);
  }

  // Collects the triangles in conflict with p, starting from t (which is),
  // and the cavity boundary counter-clockwise. The conflict region has no
  // interior vertex, so its dual is a tree and a depth-first walk that takes
  // each triangle's edges in counter-clockwise order after the entry edge
  // meets the boundary edges in order.
  void DigCavity(int32_t t, const Point2& p) {
    dead_.clear();
    boundary_.clear();
    stack_.clear();
    dead_.push_back(t);
    stack_.push_back(HalfEdge(t, 2));
    stack_.push_back(HalfEdge(t, 1));
    stack_.push_back(HalfEdge(t, 0));
    while (!stack_.empty()) {
      const int32_t h = stack_.back();
      stack_.pop_back();
      const int32_t s = TriangleOf(h), i = EdgeOf(h);
      const int32_t g = twin_[3 * s + i];
      const int32_t u = TriangleOf(g);
      if (InConflict(u, p)) {
        dead_.push_back(u);
        const int j = EdgeOf(g);
        stack_.push_back(HalfEdge(u, Prev(j)));
        stack_.push_back(HalfEdge(u, Next(j)));
      } else {
        boundary_.push_back({vertex_[3 * s + Next(i)], vertex_[3 * s + Prev(i)], g});
      }
    }
  }

  // Replaces the cavity by the fan of triangles (from, to, v), reusing the
  // dead triangles' slots first.
  void FillCavity(int32_t v) {
    const std::size_t m = boundary_.size();
    fan_.resize(m);
    for (std::size_t k = 0; k < m; ++k) {
      if (k < dead_.size()) {
        fan_[k] = dead_[k];
        SetTriangle(dead_[k], boundary_[k].from, boundary_[k].to, v);
      } else {
        fan_[k] = AddTriangle(boundary_[k].from, boundary_[k].to, v);
      }
    }
    for (std::size_t k = 0; k < m; ++k) {
      const int32_t t = fan_[k];
      Link(HalfEdge(t, 2), boundary_[k].outer);
      Link(HalfEdge(t, 0), HalfEdge(fan_[k + 1 == m ? 0 : k + 1], 1));
      if (boundary_[k].from != kInfinite && boundary_[k].to != kInfinite) last_finite_ = t;
    }
  }

  std::vector<Point2> p_;
  std::vector<int32_t> vertex_;
  std::vector<int32_t> twin_;
  std::vector<int32_t> duplicate_of_;
  int32_t last_finite_ = 0;
  int32_t num_slots_ = 0;  // triangles in use, ghosts and reused slots included
  // Scratch reused by every insertion (no per-point allocation).
  std::vector<int32_t> dead_, stack_, fan_;
  std::vector<CavityEdge> boundary_;
};

// Moves two points that span a proper triangle with order[0] to positions 1
// and 2 of `order`. Throws if there are none.
void PutFirstTriangle(const std::vector<Point2>& points, std::vector<int32_t>& order) {
  const std::size_t n = order.size();
  const Point2& a = points[order[0]];
  std::size_t j = 1;
  while (j < n && points[order[j]].x == a.x && points[order[j]].y == a.y) ++j;
  if (j == n) throw InputError("all points have the same x and y");
  std::size_t k = j + 1;
  while (k < n && Orient2D(a, points[order[j]], points[order[k]]) == 0.0) ++k;
  if (k == n) throw InputError("all points lie on one line in xy");
  const int32_t b = order[j], c = order[k];
  order.erase(order.begin() + static_cast<std::ptrdiff_t>(k));
  order.erase(order.begin() + static_cast<std::ptrdiff_t>(j));
  order.insert(order.begin() + 1, {b, c});
}

}  // namespace

namespace delaunay_internal {

Triangulation TriangulateOneThread(const std::vector<Point2>& points, const DelaunayOptions& options) {
  const std::size_t n = points.size();
  if (n < 3) throw InputError("fewer than 3 points to triangulate");
  if (n > static_cast<std::size_t>(std::numeric_limits<int32_t>::max() / 8)) {
    throw InputError("too many points for 32-bit triangle indices");
  }
  std::vector<int32_t> order;
  if (options.spatial_sort) {
    order = SpatialOrder(points, /*brio=*/true, options.seed);
  } else {
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<int32_t>(i);
  }
  PutFirstTriangle(points, order);

  // Work on a copy in insertion order: walks and in-circle tests then touch
  // memory that was touched recently.
  std::vector<Point2> sorted(n);
  for (std::size_t k = 0; k < n; ++k) sorted[k] = points[order[k]];
  Builder builder(std::move(sorted));
  if (Orient2D(points[order[0]], points[order[1]], points[order[2]]) > 0.0) {
    builder.Start(0, 1, 2);
  } else {
    builder.Start(0, 2, 1);
  }
  for (std::size_t k = 3; k < n; ++k) builder.Insert(static_cast<int32_t>(k));

  // Duplicates: the kept vertex takes the lowest input index of its group.
  Triangulation result;
  std::vector<int32_t> label(order.begin(), order.end());  // insertion position -> input index
  const std::vector<int32_t>& duplicate_of = builder.duplicate_of();
  for (std::size_t k = 0; k < n; ++k) {
    if (duplicate_of[k] >= 0) {
      label[duplicate_of[k]] = std::min(label[duplicate_of[k]], order[k]);
      ++result.num_duplicates;
    }
  }
  result.vertex_of_input.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const int32_t kept = duplicate_of[k] >= 0 ? duplicate_of[k] : static_cast<int32_t>(k);
    result.vertex_of_input[order[k]] = label[kept];
  }

  // Compact: drop ghosts, hull neighbours become -1, and number triangles by
  // their lowest vertex (counting sort), so that spatially ordered input
  // gives a mesh whose triangles and vertices are near each other in memory.
  const std::vector<int32_t>& vertex = builder.vertex();
  const std::vector<int32_t>& twin = builder.twin();
  const int32_t num_slots = builder.num_slots();
  std::vector<int32_t> new_index(num_slots, -1);
  int32_t num_finite = 0;
  {
    std::vector<int32_t> start(n + 1, 0);
    for (int32_t t = 0; t < num_slots; ++t) {
      if (builder.IsGhost(t)) continue;
      new_index[t] = std::min({label[vertex[3 * t]], label[vertex[3 * t + 1]], label[vertex[3 * t + 2]]});
      ++start[new_index[t] + 1];
    }
    for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    num_finite = start[n];
    for (int32_t t = 0; t < num_slots; ++t) {
      if (new_index[t] >= 0) new_index[t] = start[new_index[t]]++;
    }
  }
  result.triangles.resize(3 * static_cast<std::size_t>(num_finite));
  result.neighbors.resize(3 * static_cast<std::size_t>(num_finite));
  result.vertex_triangle.assign(n, -1);
  for (int32_t t = 0; t < num_slots; ++t) {
    const int32_t f = new_index[t];
    if (f < 0) continue;
    for (int i = 0; i < 3; ++i) {
      const int32_t v = label[vertex[3 * t + i]];
      result.triangles[3 * f + i] = v;
      result.neighbors[3 * f + i] = new_index[TriangleOf(twin[3 * t + i])];
      result.vertex_triangle[v] = f;
    }
  }
  return result;
}

}  // namespace delaunay_internal

Triangulation Triangulate(const std::vector<Point2>& points, const DelaunayOptions& options) {
  Triangulation result;
  if (delaunay_internal::TriangulateInSlabs(points, options, &result)) return result;
  return delaunay_internal::TriangulateOneThread(points, options);
}

double MeshArea(const std::vector<Point2>& p, const Triangulation& mesh) {
  double twice = 0.0;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const Point2& a = p[mesh.triangles[3 * t]];
    const Point2& b = p[mesh.triangles[3 * t + 1]];
    const Point2& c = p[mesh.triangles[3 * t + 2]];
    twice += (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  }
  return 0.5 * twice;
}

}  // namespace surfreg

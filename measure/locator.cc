#include "measure/locator.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <string>

#include "measure/predicates.h"

namespace surfreg {
namespace {

inline int Next(int i) { return i == 2 ? 0 : i + 1; }
inline int Prev(int i) { return i == 0 ? 2 : i - 1; }
inline int EdgeTowards(const Triangulation& mesh, int32_t t, int32_t from) {
  return mesh.neighbors[3 * t] == from ? 0 : (mesh.neighbors[3 * t + 1] == from ? 1 : 2);
}

// For q on the line through a and b (q != a): does q lie on a's ray towards b?
inline bool OnRay(const Point2& a, const Point2& b, const Point2& q) {
  if (a.x != b.x) return (b.x > a.x) == (q.x > a.x);
  return (b.y > a.y) == (q.y > a.y);
}
// For q on a's ray towards b: is q strictly beyond b?
inline bool Beyond(const Point2& a, const Point2& b, const Point2& q) {
  if (a.x != b.x) return b.x > a.x ? q.x > b.x : q.x < b.x;
  return b.y > a.y ? q.y > b.y : q.y < b.y;
}

// Barycentric coordinates of p in triangle (A, B, C), p known (exactly) to
// be in its closure; edge `zero_edge` (or -1) holds p exactly. Accurate
// sub-areas keep them right in sliver triangles too.
std::array<double, 3> Barycentric(const Point2& A, const Point2& B, const Point2& C,
                                  const Point2& p, int zero_edge) {
  double w[3] = {Orient2DAccurate(B, C, p), Orient2DAccurate(C, A, p), Orient2DAccurate(A, B, p)};
  for (double& v : w) v = std::max(v, 0.0);
  if (zero_edge >= 0) w[zero_edge] = 0.0;
  const double sum = w[0] + w[1] + w[2];
  std::array<double, 3> result;
  for (int i = 0; i < 3; ++i) result[i] = sum > 0.0 ? w[i] / sum : 1.0 / 3.0;
  return result;
}

class Walker {
 public:
  Walker(const std::vector<Point2>& points, const Triangulation& mesh, const Point2& p)
      : points_(points), mesh_(mesh), p_(p) {}

  Location Run(int32_t t, int k);
  int64_t steps() const { return steps_; }
  // A walk longer than WalkStepLimit means an invalid mesh: give up.
  bool exhausted() const { return steps_ > limit_; }

 private:
  enum class Turn { kCorner, kAlongEdge, kOffHull };
  struct Pivot {
    Turn turn;
    int32_t triangle;
    int index;  // corner: w's local index; along edge: the far end's; off hull: hull edge
  };

  const Point2& At(int32_t t, int i) const { return points_[mesh_.triangles[3 * t + i]]; }
  int32_t Neighbor(int32_t t, int i) const { return mesh_.neighbors[3 * t + i]; }
  int LocalOf(int32_t t, int32_t vertex) const {
    return mesh_.triangles[3 * t] == vertex ? 0 : (mesh_.triangles[3 * t + 1] == vertex ? 1 : 2);
  }
  int EdgeTowards(int32_t t, int32_t from) const {
    return mesh_.neighbors[3 * t] == from ? 0 : (mesh_.neighbors[3 * t + 1] == from ? 1 : 2);
  }

  Pivot TurnAround(int32_t t, int k);
  Location Classify(int32_t t, int zero_edge_a, int zero_edge_b) const;

  const std::vector<Point2>& points_;
  const Triangulation& mesh_;
  const Point2& p_;
  int64_t steps_ = 0;
  const int64_t limit_ = WalkStepLimit(mesh_);
};

// Turns around vertex w (local k of t) to the triangle whose corner at w holds
// the direction w->p: strictly inside the corner, or along one of its edges.
// Tries one rotation sense, then the other if the hull stops it.
Walker::Pivot Walker::TurnAround(int32_t t0, int k0) {
  const int32_t w = mesh_.triangles[3 * t0 + k0];
  const Point2& W = points_[w];
  bool clockwise = Orient2D(W, At(t0, Next(k0)), p_) < 0.0;
  Pivot off_hull{Turn::kOffHull, t0, Prev(k0)};
  for (int pass = 0; pass < 2; ++pass, clockwise = !clockwise) {
    int32_t t = t0;
    int k = k0;
    for (; !exhausted();) {
      ++steps_;
      const Point2& X = At(t, Next(k));
      const Point2& Y = At(t, Prev(k));
      const double ox = Orient2D(W, X, p_);
      const double oy = Orient2D(W, Y, p_);
      if (ox > 0.0 && oy < 0.0) return {Turn::kCorner, t, k};
      if (ox == 0.0 && OnRay(W, X, p_)) return {Turn::kAlongEdge, t, Next(k)};
      if (oy == 0.0 && OnRay(W, Y, p_)) return {Turn::kAlongEdge, t, Prev(k)};
      // Clockwise crosses edge w->x (opposite y); counter-clockwise edge y->w.
      const int edge = clockwise ? Prev(k) : Next(k);
      const int32_t next = Neighbor(t, edge);
      if (next < 0) {
        off_hull = {Turn::kOffHull, t, edge};
        break;
      }
      if (next == t0) return off_hull;  // full turn: only if p == w, handled by the caller
      t = next;
      k = LocalOf(t, w);
    }
  }
  return off_hull;
}

// p is in the closure of t; the listed edges (or -1) have p exactly on them.
Location Walker::Classify(int32_t t, int zero_edge_a, int zero_edge_b) const {
  Location location;
  location.triangle = t;
  if (zero_edge_a >= 0 && zero_edge_b >= 0) {
    location.where = Where::kOnVertex;
    location.index = static_cast<int8_t>(3 - zero_edge_a - zero_edge_b);
    location.barycentric[location.index] = 1.0;
    return location;
  }
  location.where = zero_edge_a >= 0 ? Where::kOnEdge : Where::kInside;
  location.index = static_cast<int8_t>(zero_edge_a);
  location.barycentric = Barycentric(At(t, 0), At(t, 1), At(t, 2), p_, zero_edge_a);
  return location;
}

Location Walker::Run(int32_t t, int k) {
  while (!exhausted()) {
    const Point2& W = At(t, k);
    if (SamePoint(W, p_)) return Classify(t, Next(k), Prev(k));
    const Pivot pivot = TurnAround(t, k);
    if (pivot.turn == Turn::kOffHull) {
      Location outside;
      outside.triangle = pivot.triangle;
      outside.index = static_cast<int8_t>(pivot.index);
      return outside;
    }
    if (pivot.turn == Turn::kAlongEdge) {
      const Point2& X = At(pivot.triangle, pivot.index);
      const int w_local = LocalOf(pivot.triangle, mesh_.triangles[3 * t + k]);
      if (SamePoint(X, p_)) return Classify(pivot.triangle, Next(pivot.index), Prev(pivot.index));
      if (!Beyond(W, X, p_)) return Classify(pivot.triangle, 3 - w_local - pivot.index, -1);
      t = pivot.triangle;  // continue from the far end of the edge
      k = pivot.index;
      continue;
    }
    // Inside the corner at w: the segment w->p leaves through the far edge.
    int32_t current = pivot.triangle;
    int exit = pivot.index;
    const double far = Orient2D(At(current, Next(exit)), At(current, Prev(exit)), p_);
    if (far > 0.0) return Classify(current, -1, -1);
    if (far == 0.0) return Classify(current, exit, -1);
    bool pivoted = false;
    while (!pivoted && !exhausted()) {
      const int32_t next = Neighbor(current, exit);
      ++steps_;
      if (next < 0) {
        Location outside;
        outside.triangle = current;
        outside.index = static_cast<int8_t>(exit);
        return outside;
      }
      const int j = EdgeTowards(next, current);  // entered through edge a->b
      const Point2& C = At(next, j);
      const double o1 = Orient2D(At(next, Prev(j)), C, p_);  // edge b->c
      const double o2 = Orient2D(C, At(next, Next(j)), p_);  // edge c->a
      if (o1 >= 0.0 && o2 >= 0.0) {
        return Classify(next, o1 == 0.0 ? Next(j) : (o2 == 0.0 ? Prev(j) : -1),
                        o1 == 0.0 && o2 == 0.0 ? Prev(j) : -1);
      }
      // a is left of the line w->p and b right: the exit edge joins c to
      // the end on its other side, unless the line runs through c itself.
      const double oc = Orient2D(W, p_, C);
      if (oc == 0.0) {
        t = next;
        k = j;
        pivoted = true;
      } else {
        current = next;
        exit = oc < 0.0 ? Prev(j) : Next(j);
      }
    }
  }
  return Location();
}

}  // namespace

int64_t WalkStepLimit(const Triangulation& mesh) {
  return 4 * static_cast<int64_t>(mesh.num_triangles()) + 64;
}

Location LocatePoint(const std::vector<Point2>& points, const Triangulation& mesh, const Point2& p,
                     int32_t start_triangle, int* steps) {
  // Most re-locations after a small motion: p strictly inside the start
  // triangle, every sub-area accurate (Orient2DClear). The walk would stop
  // there after one step and Barycentric would compute these same values.
  if (start_triangle >= 0 && start_triangle < mesh.num_triangles()) {
    const int32_t* v = &mesh.triangles[3 * start_triangle];
    const Point2& a = points[v[0]];
    const Point2& b = points[v[1]];
    const Point2& c = points[v[2]];
    double w[3];
    if (Orient2DClear(b, c, p, &w[0]) && w[0] > 0.0 && Orient2DClear(c, a, p, &w[1]) &&
        w[1] > 0.0 && Orient2DClear(a, b, p, &w[2]) && w[2] > 0.0) {
      Location inside;
      inside.triangle = start_triangle;
      inside.where = Where::kInside;
      const double sum = w[0] + w[1] + w[2];
      for (int i = 0; i < 3; ++i) inside.barycentric[i] = w[i] / sum;
      if (steps != nullptr) *steps = 1;
      return inside;
    }
  }
  Walker walker(points, mesh, p);
  const Location location = walker.Run(start_triangle, 0);
  if (steps != nullptr) *steps = static_cast<int>(std::min<int64_t>(walker.steps(), INT32_MAX));
  if (walker.exhausted()) {
    throw std::logic_error(
        "the point location walk did not end within " +
        std::to_string(WalkStepLimit(mesh)) + " steps on a mesh of " +
        std::to_string(mesh.num_triangles()) + " triangles (the triangulation is invalid)");
  }
  return location;
}

Location LocatePointBruteForce(const std::vector<Point2>& points, const Triangulation& mesh,
                               const Point2& p) {
  const int32_t n = mesh.num_triangles();
  for (int32_t t = 0; t < n; ++t) {
    const Point2& A = points[mesh.triangles[3 * t]];
    const Point2& B = points[mesh.triangles[3 * t + 1]];
    const Point2& C = points[mesh.triangles[3 * t + 2]];
    const double o[3] = {Orient2D(B, C, p), Orient2D(C, A, p), Orient2D(A, B, p)};
    if (o[0] < 0.0 || o[1] < 0.0 || o[2] < 0.0) continue;
    Location location;
    location.triangle = t;
    const int zeros = (o[0] == 0.0) + (o[1] == 0.0) + (o[2] == 0.0);
    if (zeros == 2) {
      location.where = Where::kOnVertex;
      location.index = static_cast<int8_t>(o[0] != 0.0 ? 0 : (o[1] != 0.0 ? 1 : 2));
      location.barycentric[location.index] = 1.0;
      return location;
    }
    location.where = zeros == 1 ? Where::kOnEdge : Where::kInside;
    if (zeros == 1) location.index = static_cast<int8_t>(o[0] == 0.0 ? 0 : (o[1] == 0.0 ? 1 : 2));
    location.barycentric = Barycentric(A, B, C, p, location.index);
    return location;
  }
  return Location();
}

double InterpolateCanonical(const std::vector<Point2>& points, const Triangulation& mesh,
                            const std::vector<double>& values, const Location& location,
                            const Point2& p) {
  const int32_t* v = &mesh.triangles[3 * location.triangle];
  // Lexicographic (x, y): vertices are distinct points, so a total order.
  auto before = [&points](int32_t i, int32_t j) {
    return points[i].x < points[j].x || (points[i].x == points[j].x && points[i].y < points[j].y);
  };
  if (location.where == Where::kOnVertex) return values[v[location.index]];
  if (location.where == Where::kOnEdge) {
    int32_t a = v[Next(location.index)], b = v[Prev(location.index)];
    if (before(b, a)) std::swap(a, b);
    const double dx = points[b].x - points[a].x, dy = points[b].y - points[a].y;
    const double t = std::fabs(dx) >= std::fabs(dy) ? (p.x - points[a].x) / dx
                                                    : (p.y - points[a].y) / dy;
    return values[a] + t * (values[b] - values[a]);
  }
  // Inside: the least corner first, then the mesh's cyclic order (a
  // rotation keeps the orientation, so the sub-areas stay positive). With
  // it first already, the locator's coordinates are exactly these.
  int k = before(v[1], v[0]) ? 1 : 0;
  if (before(v[2], v[k])) k = 2;
  const std::array<double, 3>& l = location.barycentric;
  if (k == 0) return l[0] * values[v[0]] + l[1] * values[v[1]] + l[2] * values[v[2]];
  const int32_t a = v[k], b = v[Next(k)], c = v[Prev(k)];
  const std::array<double, 3> w = Barycentric(points[a], points[b], points[c], p, -1);
  return w[0] * values[a] + w[1] * values[b] + w[2] * values[c];
}

Location LocateCentroid(const std::vector<Point2>& points, const Triangulation& mesh,
                        const std::array<Point2, 3>& corners, int32_t start_triangle) {
  const int32_t n = mesh.num_triangles();
  const Point2* g = corners.data();
  // Where g lies in triangle t: the exact sign for each edge (edge i is
  // opposite local vertex i), or false if it lies strictly beyond edge
  // `*beyond` (one other than `skip`, the edge the walk came in through).
  auto signs = [&](int32_t t, int skip, int o[3], int* beyond) {
    const int32_t* v = &mesh.triangles[3 * t];
    *beyond = -1;
    for (int i = 0; i < 3; ++i) {
      if (i == skip) {
        o[i] = 1;  // g is strictly on this side: the walk crossed towards it
        continue;
      }
      o[i] = Orient2DCentroidSign(points[v[Next(i)]], points[v[Prev(i)]], g);
      if (o[i] < 0 && *beyond < 0) *beyond = i;
    }
    return *beyond < 0;
  };
  auto classify = [&](int32_t t, const int o[3]) {
    const int32_t* v = &mesh.triangles[3 * t];
    Location location;
    location.triangle = t;
    const int zeros = (o[0] == 0) + (o[1] == 0) + (o[2] == 0);
    if (zeros >= 2) {
      location.where = Where::kOnVertex;
      location.index = static_cast<int8_t>(o[0] != 0 ? 0 : (o[1] != 0 ? 1 : 2));
      location.barycentric[location.index] = 1.0;
      return location;
    }
    location.where = zeros == 1 ? Where::kOnEdge : Where::kInside;
    if (zeros == 1) location.index = static_cast<int8_t>(o[0] == 0 ? 0 : (o[1] == 0 ? 1 : 2));
    const Point2 rounded = {(g[0].x + g[1].x + g[2].x) / 3.0, (g[0].y + g[1].y + g[2].y) / 3.0};
    location.barycentric =
        Barycentric(points[v[0]], points[v[1]], points[v[2]], rounded, location.index);
    return location;
  };
  int o[3];
  int beyond = -1;
  int32_t t = start_triangle >= 0 && start_triangle < n ? start_triangle : 0;
  int skip = -1;
  const int64_t limit = WalkStepLimit(mesh);
  for (int64_t step = 0; step <= limit && n > 0; ++step) {
    if (signs(t, skip, o, &beyond)) return classify(t, o);
    const int32_t next = mesh.neighbors[3 * t + beyond];
    if (next < 0) {  // beyond a hull edge: outside
      Location outside;
      outside.triangle = t;
      outside.index = static_cast<int8_t>(beyond);
      return outside;
    }
    skip = EdgeTowards(mesh, next, t);
    t = next;
  }
  // A visibility walk can cycle on a non-Delaunay mesh: every triangle then.
  for (int32_t u = 0; u < n; ++u) {
    if (signs(u, -1, o, &beyond)) return classify(u, o);
  }
  return Location();
}

std::vector<Location> LocateAll(const std::vector<Point2>& points, const Triangulation& mesh,
                                const std::vector<Point2>& queries,
                                const Triangulation& query_mesh, const SpanningTree& query_tree,
                                LocateAllStats* stats, const Execution& execution) {
  std::vector<Location> result(queries.size());
  const std::vector<int32_t>& order = query_tree.order;
  const int64_t n = static_cast<int64_t>(order.size());
  // Chunks of the tree order (bounds from its size only). A chunk's first
  // point is found by a walk from the previous chunk's first, in turn; then
  // each chunk walks on its own, from the parent's triangle when the parent
  // is in the chunk, else from the point before.
  const int chunks = ChunksFor(n, 1 << 15);
  std::vector<int32_t> position(chunks > 1 ? queries.size() : 0, -1);
  std::vector<int32_t> first(chunks, 0);
  std::vector<int64_t> steps(chunks, 0);
  if (chunks > 1) {
    ForEachChunk(execution, n, chunks, [&](int, int64_t begin, int64_t end) {
      for (int64_t k = begin; k < end; ++k) position[order[k]] = static_cast<int32_t>(k);
    });
    int32_t last = 0;
    for (int c = 0; c < chunks; ++c) {
      int walked = 0;
      last = LocatePoint(points, mesh, queries[order[ChunkBegin(n, chunks, c)]], last, &walked).triangle;
      first[c] = last;
      steps[c] += walked;
    }
  }
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    int32_t last = first[c];
    int64_t walked_in_chunk = 0;
    for (int64_t k = begin; k < end; ++k) {
      const int32_t v = order[k];
      const int32_t parent = query_tree.parent[v];
      const bool parent_here = parent >= 0 && (chunks == 1 || position[parent] >= begin);
      const int32_t start = parent_here ? result[parent].triangle : last;
      int walked = 0;
      result[v] = LocatePoint(points, mesh, queries[v], start, &walked);
      walked_in_chunk += walked;
      last = result[v].triangle;
    }
    steps[c] += walked_in_chunk;
  });
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const int32_t kept = query_mesh.vertex_of_input[i];
    if (kept != static_cast<int32_t>(i)) result[i] = result[kept];
  }
  if (stats != nullptr) {
    stats->steps = 0;
    for (int64_t s : steps) stats->steps += s;
  }
  return result;
}

}  // namespace surfreg

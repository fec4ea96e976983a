#include "measure/overlay.h"

#include <algorithm>
#include <thread>
#include <utility>

#include "measure/overlay_clip.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

inline int Sign(double v) { return (v > 0.0) - (v < 0.0); }

// Signs of one B vertex against the current T_A's three edge lines
// (+1 inside, 0 on, -1 outside), valid while `stamp` is that T_A.
struct SideCache {
  int32_t stamp = -1;
  int8_t side[3] = {0, 0, 0};
};

struct HullEdge {
  int32_t triangle;
  Point2 p, q;
};

std::vector<HullEdge> HullEdges(const std::vector<Point2>& points, const Triangulation& mesh) {
  std::vector<HullEdge> edges;
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (mesh.neighbors[3 * t + i] >= 0) continue;
      edges.push_back({t, points[mesh.triangles[3 * t + (i + 1) % 3]],
                       points[mesh.triangles[3 * t + (i + 2) % 3]]});
    }
  }
  return edges;
}

// Whether the closed segments pq and rs meet (exact).
bool SegmentsMeet(const Point2& p, const Point2& q, const Point2& r, const Point2& s) {
  const int o1 = Sign(Orient2D(p, q, r)), o2 = Sign(Orient2D(p, q, s));
  const int o3 = Sign(Orient2D(r, s, p)), o4 = Sign(Orient2D(r, s, q));
  if (o1 * o2 > 0 || o3 * o4 > 0) return false;
  if (o1 != 0 || o2 != 0) return true;
  // Collinear: do their extents overlap?
  return std::max(std::min(p.x, q.x), std::min(r.x, s.x)) <=
             std::min(std::max(p.x, q.x), std::max(r.x, s.x)) &&
         std::max(std::min(p.y, q.y), std::min(r.y, s.y)) <=
             std::min(std::max(p.y, q.y), std::max(r.y, s.y));
}

// Two hulls can overlap with no vertex of either inside the other (a
// hexagram: each triangle's corners outside the other; found by
// fuzz_measure). Then a hull edge of A crosses one of B: their triangles
// meet, a seed for the search. (-1, -1) if no hull edges meet. O(hull A x
// hull B), only when no vertex was located at all.
std::pair<int32_t, int32_t> HullCrossing(const std::vector<Point2>& points_a,
                                         const Triangulation& mesh_a,
                                         const std::vector<Point2>& points_b,
                                         const Triangulation& mesh_b) {
  const std::vector<HullEdge> edges_a = HullEdges(points_a, mesh_a);
  const std::vector<HullEdge> edges_b = HullEdges(points_b, mesh_b);
  for (const HullEdge& ea : edges_a) {
    for (const HullEdge& eb : edges_b) {
      if (SegmentsMeet(ea.p, ea.q, eb.p, eb.q)) return {ea.triangle, eb.triangle};
    }
  }
  return {-1, -1};
}

// One search over the A triangles in [begin, end). Seeds for triangles
// outside the range go to `handoff` instead; `done` is shared between
// builders, each writing only its own range while they run concurrently.
class OverlayBuilder {
 public:
  OverlayBuilder(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                 const std::vector<Point2>& points_b, const Triangulation& mesh_b,
                 std::vector<char>& done, int32_t begin, int32_t end)
      : pa_(points_a), ma_(mesh_a), pb_(points_b), mb_(mesh_b),
        seed_(mesh_a.num_triangles(), -1), done_(done), begin_(begin), end_(end),
        b_stamp_(mesh_b.num_triangles(), -1), sides_(points_b.size()) {}

  bool InRange(int32_t ta) const { return ta >= begin_ && ta < end_; }

  void Seed(int32_t ta, int32_t tb) {
    if (ta < 0 || tb < 0 || seed_[ta] >= 0) return;
    seed_[ta] = tb;
    if (!InRange(ta)) {
      handoff_.push_back({ta, tb});  // another builder's; its `done` is not ours to read now
      return;
    }
    if (!done_[ta]) pending_.push_back(ta);
  }

  // Seeds from the vertex locations, for the triangles in range; if no
  // vertex of either mesh lies in the other, from crossing hull edges.
  void SeedFromLocations(const std::vector<Location>& a_in_b, const std::vector<Location>& b_in_a) {
    const auto found = [](const Location& l) { return l.found(); };
    if (std::none_of(a_in_b.begin(), a_in_b.end(), found) &&
        std::none_of(b_in_a.begin(), b_in_a.end(), found)) {
      const auto [ta, tb] = HullCrossing(pa_, ma_, pb_, mb_);
      Seed(ta, tb);  // another builder's triangle goes to the handoff
      return;
    }
    for (std::size_t v = 0; v < a_in_b.size(); ++v) {
      const int32_t ta = ma_.vertex_triangle[v];
      if (a_in_b[v].found() && ta >= 0 && InRange(ta)) Seed(ta, a_in_b[v].triangle);
    }
    for (std::size_t u = 0; u < b_in_a.size(); ++u) {
      if (b_in_a[u].found() && mb_.vertex_triangle[u] >= 0 && InRange(b_in_a[u].triangle)) {
        Seed(b_in_a[u].triangle, mb_.vertex_triangle[u]);
      }
    }
  }

  const std::vector<std::pair<int32_t, int32_t>>& handoff() const { return handoff_; }

  OverlayStats Run(const std::function<void(const OverlayCell&)>& visit) {
    std::reverse(pending_.begin(), pending_.end());  // lowest triangles first
    while (!pending_.empty()) {
      const int32_t ta = pending_.back();
      pending_.pop_back();
      if (done_[ta]) continue;
      done_[ta] = 1;
      ProcessA(ta, visit);
    }
    return stats_;
  }

 private:
  const int8_t* Sides(int32_t u) {
    SideCache& cache = sides_[u];
    if (cache.stamp != ta_) {
      cache.stamp = ta_;
      for (int i = 0; i < 3; ++i) {
        cache.side[i] = static_cast<int8_t>(Sign(Orient2D(a_[(i + 1) % 3], a_[(i + 2) % 3], pb_[u])));
      }
    }
    return cache.side;
  }

  // o[j][k]: the sign of T_A's vertex k against tb's edge line j.
  void EdgeSigns(int32_t tb, int o[3][3]) const {
    for (int j = 0; j < 3; ++j) {
      const Point2& p = pb_[mb_.triangles[3 * tb + (j + 1) % 3]];
      const Point2& q = pb_[mb_.triangles[3 * tb + (j + 2) % 3]];
      for (int k = 0; k < 3; ++k) o[j][k] = Sign(Orient2D(p, q, a_[k]));
    }
  }

  // Whether the closures of T_A and tb meet: no edge line of either has the
  // other triangle strictly outside. Sets *have_o if it filled o (EdgeSigns).
  bool Meets(int32_t tb, const int8_t* s[3], int o[3][3], bool* have_o) const {
    *have_o = false;
    bool corner_inside = false;  // a corner of tb in T_A's closure decides at once
    for (int k = 0; k < 3; ++k) corner_inside |= s[k][0] >= 0 && s[k][1] >= 0 && s[k][2] >= 0;
    if (corner_inside) return true;
    for (int i = 0; i < 3; ++i) {
      if (s[0][i] < 0 && s[1][i] < 0 && s[2][i] < 0) return false;
    }
    EdgeSigns(tb, o);
    *have_o = true;
    for (int j = 0; j < 3; ++j) {
      if (o[j][0] < 0 && o[j][1] < 0 && o[j][2] < 0) return false;
    }
    return true;
  }

  // Hands tb to the A neighbours across T_A's edges that tb's closure meets.
  void Propagate(int32_t ta, const int8_t* s[3], int o[3][3], bool have_o, int32_t tb) {
    for (int i = 0; i < 3; ++i) {
      const int32_t next = ma_.neighbors[3 * ta + i];
      if (next < 0 || seed_[next] >= 0) continue;
      const int e0 = (i + 1) % 3, e1 = (i + 2) % 3;  // the edge's endpoints in T_A
      bool separated = (s[0][i] > 0 && s[1][i] > 0 && s[2][i] > 0) ||
                       (s[0][i] < 0 && s[1][i] < 0 && s[2][i] < 0);
      if (!separated && !have_o) {
        EdgeSigns(tb, o);
        have_o = true;
      }
      for (int j = 0; j < 3 && !separated; ++j) separated = o[j][e0] < 0 && o[j][e1] < 0;
      if (!separated) Seed(next, tb);
    }
  }

  void ProcessA(int32_t ta, const std::function<void(const OverlayCell&)>& visit);
  bool Clip(int32_t tb, const int8_t* s[3], OverlayCell& cell) const;

  const std::vector<Point2>& pa_;
  const Triangulation& ma_;
  const std::vector<Point2>& pb_;
  const Triangulation& mb_;
  std::vector<int32_t> seed_;   // per A triangle: a B triangle meeting it, or -1
  std::vector<char>& done_;     // per A triangle, shared
  const int32_t begin_, end_;
  std::vector<std::pair<int32_t, int32_t>> handoff_;
  std::vector<int32_t> b_stamp_;  // per B triangle: the last T_A whose search queued it
  std::vector<SideCache> sides_;  // per B vertex
  std::vector<int32_t> pending_, queue_;
  OverlayStats stats_;
  int32_t ta_ = -1;
  Point2 a_[3];
};

void OverlayBuilder::ProcessA(int32_t ta, const std::function<void(const OverlayCell&)>& visit) {
  ta_ = ta;
  for (int k = 0; k < 3; ++k) a_[k] = pa_[ma_.triangles[3 * ta + k]];
  queue_.clear();
  queue_.push_back(seed_[ta]);
  b_stamp_[seed_[ta]] = ta;
  OverlayCell cell;
  cell.triangle_a = ta;
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const int32_t tb = queue_[head];
    ++stats_.pairs_tested;
    const int8_t* s[3] = {Sides(mb_.triangles[3 * tb]), Sides(mb_.triangles[3 * tb + 1]),
                          Sides(mb_.triangles[3 * tb + 2])};
    int o[3][3];
    bool have_o;
    if (!Meets(tb, s, o, &have_o)) continue;
    if (Clip(tb, s, cell)) {
      cell.triangle_b = tb;
      ++stats_.cells;
      visit(cell);
    }
    Propagate(ta, s, o, have_o, tb);
    for (int j = 0; j < 3; ++j) {
      const int32_t next = mb_.neighbors[3 * tb + j];
      if (next >= 0 && b_stamp_[next] != ta) {
        b_stamp_[next] = ta;
        queue_.push_back(next);
      }
    }
  }
}

// tb clipped by T_A's three half-planes (overlay_clip.h: the one clip the
// kept overlay shares). Returns false for an empty or zero-area result.
bool OverlayBuilder::Clip(int32_t tb, const int8_t* s[3], OverlayCell& cell) const {
  const int32_t* v = &mb_.triangles[3 * tb];
  const Point2 b[3] = {pb_[v[0]], pb_[v[1]], pb_[v[2]]};
  double x[8], y[8], twice_area = 0.0;
  const int n = overlay_internal::ClipTriangle(a_, b, s, x, y, &twice_area, nullptr);
  if (n < 3) return false;
  cell.num_vertices = n;
  for (int k = 0; k < n; ++k) cell.vertices[k] = {x[k], y[k]};
  cell.area = 0.5 * twice_area;
  return true;
}

}  // namespace

OverlayStats ForEachOverlayCell(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                                const std::vector<Location>& a_in_b,
                                const std::vector<Point2>& points_b, const Triangulation& mesh_b,
                                const std::vector<Location>& b_in_a,
                                const std::function<void(const OverlayCell&)>& visit) {
  // Seeds: a triangle of A at each of A's vertices located in B, and the
  // triangle of A holding each of B's vertices.
  std::vector<char> done(mesh_a.num_triangles(), 0);
  OverlayBuilder builder(points_a, mesh_a, points_b, mesh_b, done, 0, mesh_a.num_triangles());
  builder.SeedFromLocations(a_in_b, b_in_a);
  return builder.Run(visit);
}

OverlayStats ForEachOverlayCellInTwo(const std::vector<Point2>& points_a,
                                     const Triangulation& mesh_a,
                                     const std::vector<Location>& a_in_b,
                                     const std::vector<Point2>& points_b,
                                     const Triangulation& mesh_b,
                                     const std::vector<Location>& b_in_a,
                                     const std::function<void(const OverlayCell&)>& visit_first,
                                     const std::function<void(const OverlayCell&)>& visit_second) {
  const int32_t n = mesh_a.num_triangles();
  const int32_t middle = n / 2;
  std::vector<char> done(n, 0);
  OverlayBuilder first(points_a, mesh_a, points_b, mesh_b, done, 0, middle);
  OverlayBuilder second(points_a, mesh_a, points_b, mesh_b, done, middle, n);
  OverlayStats second_stats;
  std::thread worker([&] {
    second.SeedFromLocations(a_in_b, b_in_a);
    second_stats = second.Run(visit_second);
  });
  first.SeedFromLocations(a_in_b, b_in_a);
  OverlayStats stats = first.Run(visit_first);
  worker.join();
  // Triangles reached only across the boundary between the halves.
  OverlayBuilder rest(points_a, mesh_a, points_b, mesh_b, done, 0, n);
  for (const auto* handoff : {&first.handoff(), &second.handoff()}) {
    for (const auto& [ta, tb] : *handoff) rest.Seed(ta, tb);
  }
  const OverlayStats rest_stats = rest.Run(visit_first);
  stats.cells += second_stats.cells + rest_stats.cells;
  stats.pairs_tested += second_stats.pairs_tested + rest_stats.pairs_tested;
  return stats;
}

}  // namespace surfreg

#include "measure/enforce_triangles.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "measure/predicates.h"

namespace surfreg {
namespace {

inline int Next(int i) { return i == 2 ? 0 : i + 1; }
inline int Prev(int i) { return i == 0 ? 2 : i - 1; }

inline int Sign(double d) { return d > 0.0 ? 1 : (d < 0.0 ? -1 : 0); }

// For a, u, v already known to be collinear (a, v != u): whether a lies on
// the ray from u through v. Signs of double differences are exact.
inline bool SameDirection(const Point2& u, const Point2& a, const Point2& v) {
  const int ax = Sign(a.x - u.x), vx = Sign(v.x - u.x);
  if (ax != 0 || vx != 0) return ax == vx;
  return Sign(a.y - u.y) == Sign(v.y - u.y);
}

class Enforcer {
 public:
  Enforcer(const std::vector<Point2>& points, Triangulation* mesh)
      : points_(points),
        tri_(mesh->triangles),
        nbr_(mesh->neighbors),
        vertex_triangle_(mesh->vertex_triangle),
        num_triangles_(mesh->num_triangles()) {}

  // Protects every edge of the usable required triangles from flips: a table
  // of the required triangles around each vertex (counting sort, linear).
  void LockRequired(const std::vector<int32_t>& required, const std::vector<uint8_t>& usable) {
    required_ = &required;
    lock_offset_.assign(vertex_triangle_.size() + 1, 0);
    for (std::size_t r = 0; r < usable.size(); ++r) {
      if (!usable[r]) continue;
      for (int i = 0; i < 3; ++i) ++lock_offset_[required[3 * r + i] + 1];
    }
    for (std::size_t v = 0; v + 1 < lock_offset_.size(); ++v)
      lock_offset_[v + 1] += lock_offset_[v];
    lock_triangle_.resize(lock_offset_.back());
    std::vector<int32_t> fill(lock_offset_.begin(), lock_offset_.end() - 1);
    for (std::size_t r = 0; r < usable.size(); ++r) {
      if (!usable[r]) continue;
      for (int i = 0; i < 3; ++i)
        lock_triangle_[fill[required[3 * r + i]]++] = static_cast<int32_t>(r);
    }
  }

  bool HasEdge(int32_t a, int32_t b) {
    return VisitFan(a, [&](int32_t t, int k) {
      return tri_[3 * t + Next(k)] == b || tri_[3 * t + Prev(k)] == b;
    });
  }

  // Whether (a, b, c), counter-clockwise, is a face: the triangle on the
  // left of a->b has c as its third vertex.
  bool HasFace(int32_t a, int32_t b, int32_t c) {
    return VisitFan(a, [&](int32_t t, int k) {
      return tri_[3 * t + Next(k)] == b && tri_[3 * t + Prev(k)] == c;
    });
  }

  // Makes u-v an edge by flipping the edges that cross it. False when it
  // cannot be one (a vertex on the open segment, a crossing required edge)
  // or the flip budget runs out; the mesh stays valid either way.
  bool Recover(int32_t u, int32_t v) {
    queue_.clear();
    head_ = 0;
    if (!CollectCrossings(u, v)) return false;
    const int64_t k = static_cast<int64_t>(queue_.size());
    // Safety cap only (Sloan's queue has no simple bound we rely on): in
    // stress runs recovering whole affinely stretched triangulations (random,
    // clustered, grids; k up to 120) it needed at most 4.2 k iterations.
    const int64_t budget = 256 + 16 * k * (k + 1);
    const Point2& pu = points_[u];
    const Point2& pv = points_[v];
    for (int64_t iteration = 0; head_ < queue_.size(); ++iteration) {
      if (iteration >= budget) return false;
      const std::pair<int32_t, int32_t> e = queue_[head_++];
      CompactQueue();
      int32_t t = -1;
      int i = -1;
      if (!FindEdge(e.first, e.second, &t, &i)) return false;  // broken adjacency
      const int32_t t2 = nbr_[3 * t + i];
      if (t2 < 0) return false;  // a hull edge cannot cross a segment between vertices
      const int j = OppositeLocal(t2, e.first, e.second);
      const int32_t p = tri_[3 * t + i], x = tri_[3 * t + Next(i)], y = tri_[3 * t + Prev(i)];
      const int32_t q = tri_[3 * t2 + j];
      // Strictly convex exactly when both new triangles are counter-clockwise.
      if (!(Orient2D(points_[p], points_[x], points_[q]) > 0.0 &&
            Orient2D(points_[q], points_[y], points_[p]) > 0.0)) {
        queue_.push_back(e);  // another flip may make it convex later
        continue;
      }
      Flip(t, i, t2, j);
      if (p == u || p == v || q == u || q == v) continue;  // touches uv, no crossing
      const int sp = Sign(Orient2D(pu, pv, points_[p]));
      const int sq = Sign(Orient2D(pu, pv, points_[q]));
      if (sp * sq < 0) {
        if (IsRequired(p, q)) return false;  // required edges crossing: overlap
        queue_.emplace_back(p, q);
      }
    }
    return HasEdge(u, v);
  }

 private:
  int LocalIndex(int32_t t, int32_t v) const {
    const int32_t* c = &tri_[3 * t];
    return c[0] == v ? 0 : (c[1] == v ? 1 : (c[2] == v ? 2 : -1));
  }

  // Local index in t of the vertex that is neither a nor b.
  int OppositeLocal(int32_t t, int32_t a, int32_t b) const {
    for (int j = 0; j < 3; ++j) {
      const int32_t w = tri_[3 * t + j];
      if (w != a && w != b) return j;
    }
    return 0;  // not reached on a valid mesh
  }

  // Whether a-b is an edge of a usable required triangle.
  bool IsRequired(int32_t a, int32_t b) const {
    for (int32_t k = lock_offset_[a]; k < lock_offset_[a + 1]; ++k) {
      const int32_t* c = &(*required_)[3 * static_cast<std::size_t>(lock_triangle_[k])];
      if (c[0] == b || c[1] == b || c[2] == b) return true;
    }
    return false;
  }

  // Calls visit(t, k) for each triangle t around vertex v (k: v's local
  // index), counter-clockwise from vertex_triangle[v], then clockwise from it
  // if the fan is open (hull vertex). Stops and returns true when visit does.
  // Steps are capped by the triangle count so corrupted adjacency cannot loop.
  template <typename Visit>
  bool VisitFan(int32_t v, Visit&& visit) const {
    const int32_t t0 = vertex_triangle_[v];
    if (t0 < 0) return false;
    const int k0 = LocalIndex(t0, v);
    if (k0 < 0) return false;
    int32_t t = t0;
    int k = k0;
    for (int32_t step = 0; step < num_triangles_; ++step) {
      if (visit(t, k)) return true;
      t = nbr_[3 * t + Next(k)];  // across edge (v, third vertex): the CCW side
      if (t == t0) return false;  // closed fan: all visited
      if (t < 0) break;
      k = LocalIndex(t, v);
      if (k < 0) return false;
    }
    t = nbr_[3 * t0 + Prev(k0)];  // across edge (v, second vertex): the CW side
    for (int32_t step = 0; step < num_triangles_ && t >= 0; ++step) {
      k = LocalIndex(t, v);
      if (k < 0) return false;
      if (visit(t, k)) return true;
      t = nbr_[3 * t + Prev(k)];
    }
    return false;
  }

  // A triangle t and local index i such that edge {a, b} is opposite i.
  bool FindEdge(int32_t a, int32_t b, int32_t* t_out, int* i_out) const {
    return VisitFan(a, [&](int32_t t, int k) {
      if (tri_[3 * t + Next(k)] == b) {
        *t_out = t;
        *i_out = Prev(k);
        return true;
      }
      if (tri_[3 * t + Prev(k)] == b) {
        *t_out = t;
        *i_out = Next(k);
        return true;
      }
      return false;
    });
  }

  // Walks from u along segment uv and queues every edge it crosses (each
  // given once, in order). False if a vertex lies on the open segment, a
  // crossing edge is required, or the walk fails (invalid mesh).
  bool CollectCrossings(int32_t u, int32_t v) {
    const Point2& pu = points_[u];
    const Point2& pv = points_[v];
    bool blocked = false;
    int32_t t = -1;
    int k = -1;
    // The wedge of u's fan strictly containing direction u->v: its triangle
    // (u, a, b) has a strictly right of uv and b strictly left.
    VisitFan(u, [&](int32_t tt, int kk) {
      const Point2& pa = points_[tri_[3 * tt + Next(kk)]];
      const Point2& pb = points_[tri_[3 * tt + Prev(kk)]];
      const double oa = Orient2D(pu, pa, pv);
      const double ob = Orient2D(pu, pb, pv);
      if ((oa == 0.0 && SameDirection(pu, pa, pv)) || (ob == 0.0 && SameDirection(pu, pb, pv))) {
        blocked = true;  // a fan vertex on the segment (v itself is not a neighbour)
        return true;
      }
      if (oa > 0.0 && ob < 0.0) {
        t = tt;
        k = kk;
        return true;
      }
      return false;
    });
    if (blocked || t < 0) return false;
    // Invariant: the segment leaves t through the edge opposite k, from
    // a = tri[k+1] (right of uv) to b = tri[k+2] (left).
    for (int32_t step = 0; step < num_triangles_; ++step) {
      const int32_t a = tri_[3 * t + Next(k)], b = tri_[3 * t + Prev(k)];
      if (IsRequired(a, b)) return false;  // it crosses a required edge: overlap
      queue_.emplace_back(a, b);
      const int32_t t2 = nbr_[3 * t + k];
      if (t2 < 0) return false;
      const int j = OppositeLocal(t2, a, b);  // t2 = (w, b, a) from local j
      const int32_t w = tri_[3 * t2 + j];
      if (w == v) return true;
      const double o = Orient2D(pu, pv, points_[w]);
      if (o == 0.0) return false;  // w on the open segment (v would lie in t2 otherwise)
      t = t2;
      k = o < 0.0 ? Prev(j) : Next(j);  // exit by (w, b) if w is right, else (a, w)
    }
    return false;
  }

  // Flips the edge shared by t (opposite local i) and t2 (opposite local j):
  // t = (p, x, y), t2 = (q, y, x) become t = (p, x, q), t2 = (q, y, p).
  void Flip(int32_t t, int i, int32_t t2, int j) {
    const int32_t p = tri_[3 * t + i], x = tri_[3 * t + Next(i)], y = tri_[3 * t + Prev(i)];
    const int32_t q = tri_[3 * t2 + j];
    const int32_t n_yp = nbr_[3 * t + Next(i)], n_px = nbr_[3 * t + Prev(i)];
    const int32_t n_xq = nbr_[3 * t2 + Next(j)], n_qy = nbr_[3 * t2 + Prev(j)];
    int32_t* a = &tri_[3 * t];
    a[0] = p, a[1] = x, a[2] = q;
    int32_t* an = &nbr_[3 * t];
    an[0] = n_xq, an[1] = t2, an[2] = n_px;
    int32_t* b = &tri_[3 * t2];
    b[0] = q, b[1] = y, b[2] = p;
    int32_t* bn = &nbr_[3 * t2];
    bn[0] = n_yp, bn[1] = t, bn[2] = n_qy;
    // The two outer triangles that changed sides now name the other one.
    Redirect(n_xq, t2, t);
    Redirect(n_yp, t, t2);
    vertex_triangle_[x] = t;  // x and y each lost one of the two triangles
    vertex_triangle_[y] = t2;
  }

  void Redirect(int32_t n, int32_t from, int32_t to) {
    if (n < 0) return;
    for (int s = 0; s < 3; ++s) {
      if (nbr_[3 * n + s] == from) {
        nbr_[3 * n + s] = to;
        return;
      }
    }
  }

  // Drops the consumed front of the queue once it dominates, so a long run
  // of requeued non-convex edges does not grow the buffer without bound.
  void CompactQueue() {
    if (head_ >= 1024 && 2 * head_ >= queue_.size()) {
      queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(head_));
      head_ = 0;
    }
  }

  const std::vector<Point2>& points_;
  std::vector<int32_t>& tri_;
  std::vector<int32_t>& nbr_;
  std::vector<int32_t>& vertex_triangle_;
  const int32_t num_triangles_;
  const std::vector<int32_t>* required_ = nullptr;
  std::vector<int32_t> lock_offset_;    // per vertex, into lock_triangle_
  std::vector<int32_t> lock_triangle_;  // required triangle indices around each vertex
  // Edges crossing the segment being recovered (Sloan's list), reused.
  std::vector<std::pair<int32_t, int32_t>> queue_;
  std::size_t head_ = 0;
};

}  // namespace

bool EnforceTriangles(const std::vector<Point2>& points, const std::vector<int32_t>& required,
                      Triangulation* mesh) {
  if (required.size() % 3 != 0) {
    throw std::invalid_argument("EnforceTriangles: required.size() is not a multiple of 3");
  }
  if (mesh->vertex_triangle.size() != points.size()) {
    throw std::invalid_argument("EnforceTriangles: mesh and points differ in size");
  }
  const auto n = static_cast<int64_t>(points.size());
  const std::size_t num_required = required.size() / 3;
  bool ok = true;
  // Triangles that cannot be faces whatever the flips are left out (and their
  // edges not protected), so they cannot block the others.
  std::vector<uint8_t> usable(num_required, 0);
  for (std::size_t r = 0; r < num_required; ++r) {
    const int32_t* c = &required[3 * r];
    bool valid = c[0] != c[1] && c[1] != c[2] && c[2] != c[0];
    for (int i = 0; i < 3 && valid; ++i) {
      valid = c[i] >= 0 && c[i] < n && mesh->vertex_triangle[c[i]] >= 0;
    }
    valid = valid && Orient2D(points[c[0]], points[c[1]], points[c[2]]) > 0.0;
    usable[r] = valid ? 1 : 0;
    ok = ok && valid;
  }

  Enforcer enforcer(points, mesh);
  // One fan walk per triangle finds the few that are not faces yet. A face
  // stays one: its edges are protected, and an empty triangle whose three
  // edges are in a triangulation is a face of it.
  std::vector<int32_t> missing;
  for (std::size_t r = 0; r < num_required; ++r) {
    const int32_t* c = &required[3 * r];
    if (usable[r] && !enforcer.HasFace(c[0], c[1], c[2]))
      missing.push_back(static_cast<int32_t>(r));
  }
  if (missing.empty()) return ok;
  enforcer.LockRequired(required, usable);
  for (const int32_t r : missing) {
    const int32_t* c = &required[3 * static_cast<std::size_t>(r)];
    for (int i = 0; i < 3; ++i) {
      if (!enforcer.HasEdge(c[i], c[Next(i)]) && !enforcer.Recover(c[i], c[Next(i)])) ok = false;
    }
  }
  // All three edges present but no face: another vertex inside, or an
  // overlapping required triangle took that side.
  for (const int32_t r : missing) {
    const int32_t* c = &required[3 * static_cast<std::size_t>(r)];
    if (!enforcer.HasFace(c[0], c[1], c[2])) ok = false;
  }
  return ok;
}

}  // namespace surfreg

#include "measure/delaunay.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

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
// i+2 (mod 3). Its twin[i] names the same edge seen from the neighbouring
// triangle u as the half-edge 4u + j (shifts, not divisions, to decode).
// Vertices are positions in the insertion order.
constexpr int32_t kInfinite = -1;

inline int Next(int i) { return i == 2 ? 0 : i + 1; }
inline int Prev(int i) { return i == 0 ? 2 : i - 1; }
inline int32_t HalfEdge(int32_t t, int i) { return 4 * t + i; }
inline int32_t TriangleOf(int32_t h) { return h >> 2; }
inline int EdgeOf(int32_t h) { return h & 3; }

// InCirclePerturbed(a, b, c, d) > 0, with a cheaper filter in front: the
// error bound from the largest coordinate difference m instead of the
// permanent (fewer operations per test, the build's most frequent). Rounding
// is monotone, so the computed permanent is at most 12 m^4 (1 + 2^-52) and
// |det| at most the permanent: with |det| above this bound and m^4 >= 2^-340,
// InCircle's filter accepts the same det too (its bound is lower, its
// permanent above 2^-400). Ties and doubtful cases go to InCirclePerturbed.
inline bool InCircleFast(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  constexpr double kBound = 12.0 * predicates_internal::kInCircleBound * (1.0 + 0x1p-20);
  // InCircle's own det (InCircleTermsOf).
  const predicates_internal::InCircleTerms t = predicates_internal::InCircleTermsOf(a, b, c, d);
  const double m = t.Largest();
  const double mm = m * m;
  const double m4 = mm * mm;
  const double bound = kBound * m4;
  // NaN fails every test and goes on.
  if (m <= predicates_internal::kMaxDifference && m4 >= 0x1p-340 && std::fabs(t.det) > bound)
    return t.det > 0.0;
  return InCirclePerturbed(a, b, c, d) > 0;
}

struct CavityEdge {
  int32_t from, to;  // counter-clockwise around the cavity
  int32_t outer;     // half-edge of the surviving triangle across it
};

// A triangle's corners and, per edge, the twin half-edge: one record, so a
// step of the walk or of the cavity search touches one cache line, not two.
struct Slot {
  int32_t v[3];
  int32_t twin[3];
};

// A stack of plain values that keeps its storage: push is a store and a
// compare; growing (rare: large cavities) is out of line.
template <typename T>
class Scratch {
 public:
  void clear() { size_ = 0; }
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  void push(const T& x) {
    if (size_ == data_.size()) Grow();
    data_[size_++] = x;
  }
  T pop() { return data_[--size_]; }
  const T& operator[](std::size_t k) const { return data_[k]; }

 private:
  __attribute__((noinline)) void Grow() { data_.resize(2 * data_.size() + 64); }
  std::vector<T> data_;
  std::size_t size_ = 0;
};

class Builder {
 public:
  explicit Builder(std::vector<Point2> points) : p_(std::move(points)) {
    // With the infinite vertex, k vertices make 2k - 2 triangles at any
    // time: the array never grows (no reallocation, no resize per triangle).
    // Uninitialized: every slot is written when it is first used.
    capacity_ = 2 * p_.size() + 2;
    slot_.reset(new Slot[capacity_]);
    duplicate_of_.assign(p_.size(), -1);
  }

  // Builds the first triangle from vertices a, b, c (counter-clockwise).
  void Start(int32_t a, int32_t b, int32_t c) {
    AddTriangle(a, b, c);                  // t0
    AddTriangle(c, b, kInfinite);          // t1, outside edge b->c
    AddTriangle(a, c, kInfinite);          // t2, outside edge c->a
    AddTriangle(b, a, kInfinite);          // t3, outside edge a->b
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
        const int32_t w = slot_[t].v[i];
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
  const Slot* slots() const { return slot_.get(); }
  const Point2& point(int32_t v) const { return p_[v]; }
  const std::vector<int32_t>& duplicate_of() const { return duplicate_of_; }
  bool IsGhost(int32_t t) const {
    const int32_t* v = slot_[t].v;
    return (v[0] | v[1] | v[2]) < 0;  // kInfinite is the only negative vertex
  }

 private:
  int32_t AddTriangle(int32_t a, int32_t b, int32_t c) {
    const int32_t t = num_slots_++;
    SetTriangle(t, a, b, c);
    return t;
  }
  void SetTriangle(int32_t t, int32_t a, int32_t b, int32_t c) {
    slot_[t].v[0] = a;
    slot_[t].v[1] = b;
    slot_[t].v[2] = c;
  }
  void Link(int32_t h, int32_t g) {
    slot_[TriangleOf(h)].twin[EdgeOf(h)] = g;
    slot_[TriangleOf(g)].twin[EdgeOf(g)] = h;
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
      const Slot& s = slot_[t];
      int i = first ? 0 : Next(entry);
      bool moved = false;
      for (int k = first ? 0 : 1; k < 3; ++k, i = Next(i)) {
        const int32_t a = s.v[Next(i)];
        const int32_t b = s.v[Prev(i)];
        if (Orient2D(p_[a], p_[b], p) < 0.0) {
          const int32_t h = s.twin[i];
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
    const int32_t* v = slot_[t].v;
    if ((v[0] | v[1] | v[2]) >= 0) {
      return InCircleFast(p_[v[0]], p_[v[1]], p_[v[2]], p);
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
    dead_.push(t);
    stack_.push(HalfEdge(t, 2));
    stack_.push(HalfEdge(t, 1));
    stack_.push(HalfEdge(t, 0));
    while (!stack_.empty()) {
      const int32_t h = stack_.pop();
      const Slot& s = slot_[TriangleOf(h)];
      const int i = EdgeOf(h);
      const int32_t g = s.twin[i];
      const int32_t u = TriangleOf(g);
      if (InConflict(u, p)) {
        dead_.push(u);
        const int j = EdgeOf(g);
        stack_.push(HalfEdge(u, Prev(j)));
        stack_.push(HalfEdge(u, Next(j)));
      } else {
        boundary_.push({s.v[Next(i)], s.v[Prev(i)], g});
      }
    }
  }

  // Replaces the cavity by the fan of triangles (from, to, v), reusing the
  // dead triangles' slots first (the fan has two more triangles than the
  // cavity had: those take new slots).
  void FillCavity(int32_t v) {
    const std::size_t m = boundary_.size(), reused = dead_.size();
    const int32_t fresh = num_slots_;
    num_slots_ += static_cast<int32_t>(m - reused);
    const auto fan = [&](std::size_t k) {
      return k < reused ? dead_[k] : fresh + static_cast<int32_t>(k - reused);
    };
    int32_t next = fan(0);
    for (std::size_t k = 0; k < m; ++k) {
      const int32_t t = next;
      next = fan(k + 1 == m ? 0 : k + 1);
      const CavityEdge& e = boundary_[k];
      SetTriangle(t, e.from, e.to, v);
      Link(HalfEdge(t, 2), e.outer);
      // Edge 0 (to -> v) meets edge 1 (v -> from) of the next triangle.
      slot_[t].twin[0] = HalfEdge(next, 1);
      slot_[next].twin[1] = HalfEdge(t, 0);
      if ((e.from | e.to) >= 0) last_finite_ = t;
    }
  }

  std::vector<Point2> p_;
  std::unique_ptr<Slot[]> slot_;
  std::size_t capacity_ = 0;
  std::vector<int32_t> duplicate_of_;
  int32_t last_finite_ = 0;
  int32_t num_slots_ = 0;  // triangles in use, ghosts and reused slots included
  // Scratch reused by every insertion (no per-point allocation).
  Scratch<int32_t> dead_, stack_;
  Scratch<CavityEdge> boundary_;
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

// Skinny triangles (angle at a below ~1e-4 rad) are left to the stitch; for
// the others the circle's centre and radius carry relative errors far below
// the margin.
bool CircleWithin(const Point2& a, const Point2& b, const Point2& c, double lo, double hi) {
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double bb = bx * bx + by * by, cc = cx * cx + cy * cy;
  const double d = 2.0 * (bx * cy - by * cx);
  if (!(d * d >= 4e-8 * bb * cc)) return false;
  const double inverse = 1.0 / d;
  const double ux = (cy * bb - by * cc) * inverse, uy = (bx * cc - cx * bb) * inverse;
  const double r = std::sqrt(ux * ux + uy * uy);
  const double centre = a.x + ux;
  const double margin = 1e-9 * r + 1e-14 * (std::abs(centre) + r);
  return centre - r - margin > lo && centre + r + margin < hi;
}

namespace {

// The incremental build, and each insertion position's vertex.
struct Built {
  std::vector<int32_t> order;  // insertion position -> input index
  // Insertion position -> its vertex's input index (duplicates: the lowest).
  std::vector<int32_t> label;
  std::unique_ptr<Builder> builder;
  int32_t num_duplicates = 0;
};

Built Build(const std::vector<Point2>& points, const DelaunayOptions& options) {
  const std::size_t n = points.size();
  if (n < 3) throw InputError("fewer than 3 points to triangulate");
  if (n > static_cast<std::size_t>(std::numeric_limits<int32_t>::max() / 8)) {
    throw InputError("too many points for 32-bit triangle indices");
  }
  Built built;
  std::vector<int32_t>& order = built.order;
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
  built.builder = std::make_unique<Builder>(std::move(sorted));
  Builder& builder = *built.builder;
  if (Orient2D(points[order[0]], points[order[1]], points[order[2]]) > 0.0) {
    builder.Start(0, 1, 2);
  } else {
    builder.Start(0, 2, 1);
  }
  for (std::size_t k = 3; k < n; ++k) builder.Insert(static_cast<int32_t>(k));

  // Duplicates: the kept vertex takes the lowest input index of its group.
  built.label = order;
  const std::vector<int32_t>& duplicate_of = builder.duplicate_of();
  for (std::size_t k = 0; k < n; ++k) {
    if (duplicate_of[k] >= 0) {
      built.label[duplicate_of[k]] = std::min(built.label[duplicate_of[k]], order[k]);
      ++built.num_duplicates;
    }
  }
  return built;
}

// Per input index: the input index of its vertex.
void VertexOfInput(const Built& built, std::vector<int32_t>* vertex_of_input) {
  const std::vector<int32_t>& duplicate_of = built.builder->duplicate_of();
  vertex_of_input->resize(built.order.size());
  for (std::size_t k = 0; k < built.order.size(); ++k) {
    const int32_t kept = duplicate_of[k] >= 0 ? duplicate_of[k] : static_cast<int32_t>(k);
    (*vertex_of_input)[built.order[k]] = built.label[kept];
  }
}

// How far ahead the passes over the slots fetch what a slot points to: slots
// in creation order are only roughly local (a cache miss each, else).
constexpr int32_t kAhead = 12;

}  // namespace

Triangulation TriangulateOneThread(const std::vector<Point2>& points,
                                   const DelaunayOptions& options) {
  const std::size_t n = points.size();
  const Built built = Build(points, options);
  const Builder& builder = *built.builder;
  const std::vector<int32_t>& label = built.label;
  Triangulation result;
  result.num_duplicates = built.num_duplicates;
  VertexOfInput(built, &result.vertex_of_input);

  // Compact: drop ghosts, hull neighbours become -1, and number triangles by
  // their lowest vertex (counting sort), so that spatially ordered input
  // gives a mesh whose triangles and vertices are near each other in memory.
  const Slot* slot = builder.slots();
  const int32_t num_slots = builder.num_slots();
  std::vector<int32_t> new_index(num_slots, -1);
  int32_t num_finite = 0;
  {
    std::vector<int32_t> start(n + 1, 0);
    for (int32_t t = 0; t < num_slots; ++t) {
      if (builder.IsGhost(t)) continue;
      const int32_t* v = slot[t].v;
      new_index[t] = std::min({label[v[0]], label[v[1]], label[v[2]]});
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
      const int32_t v = label[slot[t].v[i]];
      result.triangles[3 * f + i] = v;
      result.neighbors[3 * f + i] = new_index[TriangleOf(slot[t].twin[i])];
      result.vertex_triangle[v] = f;
    }
  }
  return result;
}

void TriangulateSlab(const std::vector<Point2>& points, const std::vector<int32_t>& input,
                     const DelaunayOptions& options, double lo, double hi, SlabPart* part) {
  const std::size_t n = points.size();
  const Built built = Build(points, options);
  const Builder& builder = *built.builder;
  const std::vector<int32_t>& label = built.label;
  part->num_duplicates = built.num_duplicates;
  if (built.num_duplicates > 0) {
    VertexOfInput(built, &part->kept);
    for (int32_t& k : part->kept) k = input[k];
  }

  // Per slot: ghost -2, non-final -1 (their corners, and the ghosts' ones:
  // the hull's, go to the seam); a final triangle its lowest vertex, then
  // its index among the final ones in TriangulateOneThread's order (a
  // counting sort, as there).
  const Slot* slot = builder.slots();
  const int32_t num_slots = builder.num_slots();
  const auto p = [&builder](int32_t v) -> const Point2& { return builder.point(v); };
  std::vector<int32_t> id(num_slots);
  std::vector<uint8_t> seam(n, 0);
  std::vector<int32_t> start(n + 1, 0);
  for (int32_t t = 0; t < num_slots; ++t) {
    if (t + kAhead < num_slots) {
      const int32_t* w = slot[t + kAhead].v;
      if ((w[0] | w[1] | w[2]) >= 0) {
        for (int i = 0; i < 3; ++i) __builtin_prefetch(&p(w[i]));
      }
    }
    const int32_t* v = slot[t].v;
    if ((v[0] | v[1] | v[2]) < 0) {
      id[t] = -2;
      for (int i = 0; i < 3; ++i) {
        if (v[i] >= 0) seam[label[v[i]]] = 1;
      }
    } else if (CircleWithin(p(v[0]), p(v[1]), p(v[2]), lo, hi)) {
      id[t] = std::min({label[v[0]], label[v[1]], label[v[2]]});
      ++start[id[t] + 1];
    } else {
      id[t] = -1;
      seam[label[v[0]]] = seam[label[v[1]]] = seam[label[v[2]]] = 1;
    }
  }
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  const int32_t num_final = start[n];
  part->num_final = num_final;
  for (int32_t t = 0; t < num_slots; ++t) {
    if (id[t] >= 0) id[t] = start[id[t]]++;
  }
  start = std::vector<int32_t>();

  // The final triangles with their corners' input indices; the neighbours
  // across the frontier are filled in by the stitch.
  part->triangles.resize(3 * static_cast<std::size_t>(num_final));
  part->neighbors.resize(3 * static_cast<std::size_t>(num_final));
  part->first_final.assign(n, -1);
  part->frontier.clear();
  for (int32_t t = 0; t < num_slots; ++t) {
    const int32_t f = id[t];
    if (f < 0) continue;
    const Slot& s = slot[t];
    const int32_t v[3] = {label[s.v[0]], label[s.v[1]], label[s.v[2]]};
    for (int i = 0; i < 3; ++i) {
      part->triangles[3 * f + i] = input[v[i]];
      const int32_t u = id[TriangleOf(s.twin[i])];
      part->neighbors[3 * f + i] = u >= 0 ? u : -1;
      if (u < 0) part->frontier.push_back({input[v[Next(i)]], input[v[Prev(i)]], f, i});
      // The lowest final triangle of each vertex (unsigned: -1 is above all).
      int32_t& first = part->first_final[v[i]];
      if (static_cast<uint32_t>(f) < static_cast<uint32_t>(first)) first = f;
    }
  }
  part->seam.clear();
  for (std::size_t k = 0; k < n; ++k) {
    if (seam[k]) part->seam.push_back(input[k]);
  }
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

#include "measure/overlay.h"

#include <algorithm>
#include <array>
#include <memory>
#include <mutex>
#include <utility>

#include "measure/bucket_scatter.h"
#include "measure/overlay_clip.h"
#include "measure/predicates.h"
#include "measure/tasks.h"

namespace surfreg {
namespace {

inline int Sign(double v) { return (v > 0.0) - (v < 0.0); }

// Signs of one B vertex against a T_A's three edge lines, as the clip
// takes them (+1 inside, 0 on, -1 outside) and as Orient2DEdgeSignBits
// gives them (for the tests of whole triangles).
struct VertexSides {
  int8_t side[3];
  uint8_t bits;  // bit i: side[i] > 0; bit 3 + i: side[i] < 0
};

// VertexSides by `bits`: one 4-byte copy where the signs change.
constexpr std::array<VertexSides, 64> MakeVertexSidesTable() {
  std::array<VertexSides, 64> table{};
  for (unsigned bits = 0; bits < 64; ++bits) {
    for (int i = 0; i < 3; ++i) {
      table[bits].side[i] = static_cast<int8_t>(((bits >> i) & 1) - ((bits >> (3 + i)) & 1));
    }
    table[bits].bits = static_cast<uint8_t>(bits);
  }
  return table;
}
constexpr std::array<VertexSides, 64> kVertexSides = MakeVertexSidesTable();

// A B vertex's sides, valid while `stamp` is the current T_A.
struct SideCache {
  int32_t stamp = -1;
  VertexSides sides = {{0, 0, 0}, 0};
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
                 std::vector<char>& done, bool labelled)
      : pa_(points_a), ma_(mesh_a), pb_(points_b), mb_(mesh_b), labelled_(labelled),
        seed_(mesh_a.num_triangles(), -1), done_(done),
        b_stamp_(mesh_b.num_triangles(), -1), sides_(points_b.size()) {}

  // A search over the A triangles in [begin, end), from fresh seeds.
  void Begin(int32_t begin, int32_t end) {
    begin_ = begin;
    end_ = end;
    stats_ = OverlayStats();
  }

  // Clears the seeds for the next range; returns the handoff.
  std::vector<std::pair<int32_t, int32_t>> End() {
    for (const int32_t ta : seeded_) seed_[ta] = -1;
    seeded_.clear();
    std::vector<std::pair<int32_t, int32_t>> handoff;
    handoff.swap(handoff_);
    return handoff;
  }

  bool InRange(int32_t ta) const { return ta >= begin_ && ta < end_; }

  void Seed(int32_t ta, int32_t tb) {
    if (ta < 0 || tb < 0 || seed_[ta] >= 0) return;
    seed_[ta] = tb;
    seeded_.push_back(ta);
    if (!InRange(ta)) {
      handoff_.push_back({ta, tb});  // another builder's; its `done` is not ours to read now
      return;
    }
    if (!done_[ta]) pending_.push_back(ta);
  }


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
  const VertexSides& Sides(int32_t u) {
    SideCache& cache = sides_[u];
    if (cache.stamp != ta_) {
      cache.stamp = ta_;
      cache.sides = kVertexSides[Orient2DEdgeSignBits(a_, pb_[u])];
    }
    return cache.sides;
  }

  // outside[k], bit j: T_A's vertex k strictly outside the line of tb's
  // edge j (tb's corners b).
  void EdgeSigns(const Point2 b[3], unsigned outside[3]) const {
    for (int k = 0; k < 3; ++k) outside[k] = Orient2DEdgeSignBits(b, a_[k]) >> 3;
  }

  // Whether the closures of T_A and tb meet: no edge line of either has the
  // other triangle strictly outside. `m` are the bits of tb's corners'
  // VertexSides. Sets *have_o if it filled `outside` (EdgeSigns).
  bool Meets(const Point2 b[3], const unsigned m[3], unsigned outside[3], bool* have_o) const {
    *have_o = false;
    // A corner of tb in T_A's closure (outside no line) decides at once.
    if ((m[0] & 070) == 0 || (m[1] & 070) == 0 || (m[2] & 070) == 0) return true;
    if (m[0] & m[1] & m[2] & 070) return false;  // all three outside one line
    EdgeSigns(b, outside);
    *have_o = true;
    return (outside[0] & outside[1] & outside[2]) == 0;
  }

  // Hands tb to the A neighbours across T_A's edges that tb's closure meets.
  void Propagate(int32_t ta, int32_t tb, const Point2 b[3], const unsigned m[3],
                 unsigned outside[3], bool have_o) {
    const unsigned all = m[0] & m[1] & m[2];
    const unsigned one_side = (all | all >> 3) & 7;  // bit i: tb strictly on one side of line i
    for (int i = 0; i < 3; ++i) {
      const int32_t next = ma_.neighbors[3 * ta + i];
      if (next < 0 || seed_[next] >= 0 || (one_side >> i) & 1) continue;
      if (!have_o) {
        EdgeSigns(b, outside);
        have_o = true;
      }
      static constexpr int kNext[3] = {1, 2, 0}, kPrev[3] = {2, 0, 1};  // edge i's endpoints
      if (outside[kNext[i]] & outside[kPrev[i]]) continue;  // one of tb's lines separates
      Seed(next, tb);
    }
  }

  void ProcessA(int32_t ta, const std::function<void(const OverlayCell&)>& visit);
  bool Clip(const Point2 b[3], const int8_t* s[3], OverlayCell& cell) const;

  const std::vector<Point2>& pa_;
  const Triangulation& ma_;
  const std::vector<Point2>& pb_;
  const Triangulation& mb_;
  const bool labelled_;
  std::vector<int32_t> seed_;   // per A triangle: a B triangle meeting it, or -1
  std::vector<char>& done_;     // per A triangle, shared
  int32_t begin_ = 0, end_ = 0;
  std::vector<int32_t> seeded_;  // where seed_ was set
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
    const int32_t* v = &mb_.triangles[3 * tb];
    const VertexSides* c[3] = {&Sides(v[0]), &Sides(v[1]), &Sides(v[2])};
    const unsigned m[3] = {c[0]->bits, c[1]->bits, c[2]->bits};
    const Point2 b[3] = {pb_[v[0]], pb_[v[1]], pb_[v[2]]};
    unsigned outside[3];
    bool have_o;
    if (!Meets(b, m, outside, &have_o)) continue;
    const int8_t* s[3] = {c[0]->side, c[1]->side, c[2]->side};
    if (Clip(b, s, cell)) {
      cell.triangle_b = tb;
      ++stats_.cells;
      visit(cell);
    }
    Propagate(ta, tb, b, m, outside, have_o);
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
bool OverlayBuilder::Clip(const Point2 b[3], const int8_t* s[3], OverlayCell& cell) const {
  overlay_internal::ClipPolygon scratch[2];
  const overlay_internal::ClipPolygon* polygon = nullptr;
  double twice_area = 0.0;
  const int n = labelled_ ? overlay_internal::ClipTriangleInto<true>(a_, b, s, scratch, &polygon, &twice_area)
                         : overlay_internal::ClipTriangleInto<false>(a_, b, s, scratch, &polygon, &twice_area);
  if (n < 3) return false;
  cell.num_vertices = n;
  for (int k = 0; k < n; ++k) cell.vertices[k] = {polygon->corner[k].x, polygon->corner[k].y};
  if (labelled_) std::copy(polygon->label, polygon->label + n, cell.labels.begin());
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
  return ForEachOverlayCellInChunks(points_a, mesh_a, a_in_b, points_b, mesh_b, b_in_a, 1,
                                    [&](int, const OverlayCell& cell) { visit(cell); }, Execution{1});
}

// Ranges of at least 4096 triangles: a 15,000-point face (30,000 triangles)
// is searched in 7 ranges side by side (with 16384 it was one, on one
// thread: 28% of a face alignment); at 2e5 points the 64 ranges' boundary
// triangles cost nothing measurable.
int OverlayChunks(const Triangulation& mesh_a) { return ChunksFor(mesh_a.num_triangles(), 4096); }

OverlayStats ForEachOverlayCellInChunks(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                                        const std::vector<Location>& a_in_b,
                                        const std::vector<Point2>& points_b, const Triangulation& mesh_b,
                                        const std::vector<Location>& b_in_a, int chunks,
                                        const std::function<void(int, const OverlayCell&)>& visit,
                                        const Execution& execution, bool labelled) {
  const int32_t n = mesh_a.num_triangles();
  chunks = std::max(1, chunks);
  const auto chunk_of = [&](int32_t ta) {
    // The chunk whose [ChunkBegin(c), ChunkBegin(c + 1)) holds ta.
    int c = static_cast<int>(static_cast<int64_t>(ta) * chunks / std::max(n, 1));
    while (c + 1 < chunks && ChunkBegin(n, chunks, c + 1) <= ta) ++c;
    while (c > 0 && ChunkBegin(n, chunks, c) > ta) --c;
    return c;
  };
  // Each chunk's seeds, in the order one search over all would take them
  // (A's vertices, then B's), gathered by a stable scatter in chunks:
  // chunk c's are seeds[seed_start[c], seed_start[c + 1]).
  std::vector<std::pair<int32_t, int32_t>> seeds;
  std::vector<int64_t> seed_start(static_cast<std::size_t>(chunks) + 1, 0);
  const auto found = [](const Location& l) { return l.found(); };
  if (std::none_of(a_in_b.begin(), a_in_b.end(), found) && std::none_of(b_in_a.begin(), b_in_a.end(), found)) {
    const auto [ta, tb] = HullCrossing(points_a, mesh_a, points_b, mesh_b);
    if (ta >= 0 && tb >= 0) {
      seeds.push_back({ta, tb});
      for (int c = chunk_of(ta) + 1; c <= chunks; ++c) seed_start[c] = 1;
    }
  } else {
    const int64_t na = static_cast<int64_t>(a_in_b.size());
    const int64_t items = na + static_cast<int64_t>(b_in_a.size());
    const auto seed_of = [&](int64_t i) -> std::pair<int32_t, int32_t> {
      if (i < na) {
        const int32_t ta = mesh_a.vertex_triangle[i];
        if (a_in_b[i].found() && ta >= 0) return {ta, a_in_b[i].triangle};
      } else {
        const int64_t u = i - na;
        if (b_in_a[u].found() && mesh_b.vertex_triangle[u] >= 0) return {b_in_a[u].triangle, mesh_b.vertex_triangle[u]};
      }
      return {-1, -1};
    };
    const auto bucket = [&](int64_t i) {
      const int32_t ta = seed_of(i).first;
      return ta >= 0 ? chunk_of(ta) : -1;
    };
    BucketSlots slots(ChunksFor(items, 1 << 15), chunks);
    CountIntoBuckets(execution, items, slots, bucket);
    seeds.resize(static_cast<std::size_t>(slots.start[chunks]));
    ScatterIntoBuckets(execution, items, slots, bucket, [&](int64_t i, int64_t at) { seeds[at] = seed_of(i); });
    seed_start = slots.start;
  }
  // Builders' arrays are as large as the meshes: one per running thread,
  // reused by the chunks it takes (their caches are stamped by T_A, and
  // each T_A is searched once, so a reused cache never answers wrongly).
  std::vector<char> done(n, 0);
  std::mutex pool_mutex;
  std::vector<std::unique_ptr<OverlayBuilder>> pool;
  const auto take = [&] {
    std::lock_guard<std::mutex> lock(pool_mutex);
    if (pool.empty()) return std::make_unique<OverlayBuilder>(points_a, mesh_a, points_b, mesh_b, done, labelled);
    std::unique_ptr<OverlayBuilder> b = std::move(pool.back());
    pool.pop_back();
    return b;
  };
  std::vector<std::vector<std::pair<int32_t, int32_t>>> handoffs(chunks);
  std::vector<OverlayStats> stats(chunks);
  ForEachChunk(execution, n, chunks, [&](int c, int64_t lo, int64_t hi) {
    std::unique_ptr<OverlayBuilder> builder = take();
    builder->Begin(static_cast<int32_t>(lo), static_cast<int32_t>(hi));
    for (int64_t k = seed_start[c]; k < seed_start[c + 1]; ++k) builder->Seed(seeds[k].first, seeds[k].second);
    stats[c] = builder->Run([&](const OverlayCell& cell) { visit(c, cell); });
    handoffs[c] = builder->End();
    std::lock_guard<std::mutex> lock(pool_mutex);
    pool.push_back(std::move(builder));
  });
  // Triangles reached only across the boundaries between the chunks.
  std::unique_ptr<OverlayBuilder> rest = take();
  rest->Begin(0, n);
  for (const auto& handoff : handoffs) {
    for (const auto& [ta, tb] : handoff) rest->Seed(ta, tb);
  }
  OverlayStats total = rest->Run([&](const OverlayCell& cell) { visit(0, cell); });
  for (const OverlayStats& s : stats) {
    total.cells += s.cells;
    total.pairs_tested += s.pairs_tested;
  }
  return total;
}

}  // namespace surfreg

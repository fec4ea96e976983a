#include "registration/volume_cost/overlay_topology.h"

#include <algorithm>
#include <limits>

#include "measure/overlay.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

inline int Sign(double v) { return (v > 0.0) - (v < 0.0); }

// The full overlay's clip (measure/overlay_clip.h), with labels: so the
// cells kept are exactly the ones it keeps. Returns the number of corners,
// 0 for an empty or zero-area result.
int ClipLabeled(const Point2 a[3], const Point2 b[3], const int8_t s[3][3], uint8_t* code) {
  const int8_t* const sides[3] = {s[0], s[1], s[2]};
  double x[8], y[8], twice_area;
  return overlay_internal::ClipTriangle(a, b, sides, x, y, &twice_area, code);
}

}  // namespace

// The exact search of one A triangle: a breadth-first search over the B
// triangles whose closures meet it, from seeds (as measure/overlay.cc).
struct OverlayTopology::Searcher {
  std::vector<int32_t> b_stamp;     // per B triangle: the search that queued it
  std::vector<int32_t> side_stamp;  // per B vertex: the search its `sides` are for
  std::vector<std::array<int8_t, 3>> sides;
  std::vector<int32_t> queue;
  int32_t stamp = 0;
  TopologyStats stats;  // of the chunk it searches for
  // Current A triangle.
  const std::vector<Point2>* pb = nullptr;
  const Triangulation* mb = nullptr;
  const uint8_t* keep_b = nullptr;  // null: all
  Point2 a[3];

  void Size(int32_t num_b_triangles, int64_t num_b_points) {
    if (static_cast<int32_t>(b_stamp.size()) != num_b_triangles) b_stamp.assign(num_b_triangles, -1);
    if (static_cast<int64_t>(side_stamp.size()) != num_b_points) {
      side_stamp.assign(num_b_points, -1);
      sides.resize(num_b_points);
    }
    stats = TopologyStats();
  }

  void Begin(const Point2* corners) {
    if (stamp == std::numeric_limits<int32_t>::max()) {
      std::fill(b_stamp.begin(), b_stamp.end(), -1);
      std::fill(side_stamp.begin(), side_stamp.end(), -1);
      stamp = 0;
    }
    ++stamp;
    for (int k = 0; k < 3; ++k) a[k] = corners[k];
    queue.clear();
    ++stats.triangles_searched;
  }

  void Push(int32_t tb) {
    if (tb < 0 || b_stamp[tb] == stamp) return;
    b_stamp[tb] = stamp;
    queue.push_back(tb);
  }

  const int8_t* Sides(int32_t u) {
    if (side_stamp[u] != stamp) {
      side_stamp[u] = stamp;
      for (int i = 0; i < 3; ++i) {
        sides[u][i] = static_cast<int8_t>(Sign(Orient2D(a[(i + 1) % 3], a[(i + 2) % 3], (*pb)[u])));
      }
    }
    return sides[u].data();
  }

  // Whether the closures of T_A and tb meet: no edge line of either has the
  // other triangle strictly outside.
  bool Meets(int32_t tb, const int8_t* s[3]) const {
    for (int k = 0; k < 3; ++k) {
      if (s[k][0] >= 0 && s[k][1] >= 0 && s[k][2] >= 0) return true;
    }
    for (int i = 0; i < 3; ++i) {
      if (s[0][i] < 0 && s[1][i] < 0 && s[2][i] < 0) return false;
    }
    const int32_t* v = &mb->triangles[3 * tb];
    for (int j = 0; j < 3; ++j) {
      const Point2& p = (*pb)[v[(j + 1) % 3]];
      const Point2& q = (*pb)[v[(j + 2) % 3]];
      if (Orient2D(p, q, a[0]) < 0 && Orient2D(p, q, a[1]) < 0 && Orient2D(p, q, a[2]) < 0) return false;
    }
    return true;
  }

  // Runs the queued search; appends the cells to `out`. Returns whether any
  // B triangle met T_A.
  bool Run(std::vector<TopologyCell>* out) {
    bool met = false;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int32_t tb = queue[head];
      ++stats.pairs_tested;
      const int32_t* v = &mb->triangles[3 * tb];
      const int8_t* s[3] = {Sides(v[0]), Sides(v[1]), Sides(v[2])};
      if (!Meets(tb, s)) continue;
      met = true;
      int8_t signs[3][3];
      for (int k = 0; k < 3; ++k) std::copy(s[k], s[k] + 3, signs[k]);
      const Point2 b[3] = {(*pb)[v[0]], (*pb)[v[1]], (*pb)[v[2]]};
      TopologyCell cell{};
      cell.triangle_b = tb;
      cell.num_corners = static_cast<uint8_t>(ClipLabeled(a, b, signs, cell.corner.data()));
      if (cell.num_corners >= 3 && (keep_b == nullptr || keep_b[tb])) out->push_back(cell);
      for (int j = 0; j < 3; ++j) Push(mb->neighbors[3 * tb + j]);
    }
    return met;
  }
};

OverlayTopology::OverlayTopology() = default;
OverlayTopology::~OverlayTopology() = default;

// A searcher is scratch only (what a chunk finds does not depend on which
// one it used): lent to one chunk at a time, as many made as ran at once.
std::unique_ptr<OverlayTopology::Searcher> OverlayTopology::Lend(int32_t num_b_triangles, int64_t num_b_points) {
  std::unique_ptr<Searcher> s;
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    if (!pool_.empty()) {
      s = std::move(pool_.back());
      pool_.pop_back();
    }
  }
  if (!s) s = std::make_unique<Searcher>();
  s->Size(num_b_triangles, num_b_points);
  return s;
}

void OverlayTopology::Return(std::unique_ptr<Searcher> s) {
  std::lock_guard<std::mutex> lock(pool_mutex_);
  pool_.push_back(std::move(s));
}

// Chunks of A triangles: the cells do not depend on them (each T_A's are
// found on their own, and kept in T_A order).
int OverlayTopology::Chunks(int32_t num_a_triangles) { return ChunksFor(num_a_triangles, 4096); }

TopologyStats OverlayTopology::Build(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                                     const std::vector<Location>& a_in_b,
                                     const std::vector<Point2>& points_b, const Triangulation& mesh_b,
                                     const std::vector<Location>& b_in_a, const Execution& execution,
                                     const uint8_t* keep_a, const uint8_t* keep_b) {
  const int32_t na = mesh_a.num_triangles();
  // The full overlay's cells with their labels (the same clip: the same
  // cells), by chunk, then by T_A: a search visits one T_A's cells in a
  // row, so a chunk's are runs (T_A, count). The same lists on any number of
  // threads (overlay.h): the cells' order, and so every sum over them, does
  // not depend on the thread count.
  const int chunks = OverlayChunks(mesh_a);
  std::vector<std::vector<TopologyCell>> found(chunks);
  std::vector<std::vector<std::pair<int32_t, int32_t>>> runs(chunks);
  // Room for about three times the cells an overlay has (fewer than both
  // meshes' triangles together, doubled), shared by the chunks as their A
  // triangles: reserved pages cost nothing until written, while a vector
  // grown by doubling keeps up to twice its cells at once.
  const int64_t expected = 6 * (static_cast<int64_t>(na) + mesh_b.num_triangles());
  for (int c = 0; c < chunks; ++c) {
    const int64_t share = ChunkBegin(na, chunks, c + 1) - ChunkBegin(na, chunks, c);
    found[c].reserve(static_cast<std::size_t>(expected * share / std::max<int32_t>(na, 1) + 256));
  }
  const OverlayStats overlay = ForEachOverlayCellInChunks(
      points_a, mesh_a, a_in_b, points_b, mesh_b, b_in_a, static_cast<int>(found.size()),
      [&](int c, const OverlayCell& cell) {
        if ((keep_a != nullptr && !keep_a[cell.triangle_a]) || (keep_b != nullptr && !keep_b[cell.triangle_b])) return;
        TopologyCell kept{};
        kept.triangle_b = cell.triangle_b;
        kept.num_corners = static_cast<uint8_t>(cell.num_vertices);
        std::copy(cell.labels.begin(), cell.labels.begin() + cell.num_vertices, kept.corner.begin());
        found[c].push_back(kept);
        if (runs[c].empty() || runs[c].back().first != cell.triangle_a) runs[c].push_back({cell.triangle_a, 0});
        ++runs[c].back().second;
      },
      execution, /*labelled=*/true);
  begin_.assign(na + 1, 0);
  count_.assign(na, 0);
  for (const auto& list : runs) {
    for (const auto& [ta, count] : list) begin_[ta + 1] += count;
  }
  for (int32_t t = 0; t < na; ++t) begin_[t + 1] += begin_[t];
  // Room for the repairs' appends until the first compaction (Compact).
  cells_.reserve(static_cast<std::size_t>(begin_[na] * 5 / 2 + 8192));
  cells_.resize(static_cast<std::size_t>(begin_[na]));  // not written: filled below
  // A chunk's runs are its own A triangles, so their places in cells_ are
  // its own: the chunks copy side by side (each first touching its pages).
  ForEachChunk(execution, chunks, chunks, [&](int, int64_t first, int64_t last) {
    for (int64_t c = first; c < last; ++c) {
      const TopologyCell* next = found[c].data();
      for (const auto& [ta, count] : runs[c]) {
        std::copy(next, next + count, cells_.begin() + begin_[ta] + count_[ta]);
        count_[ta] += count, next += count;
      }
      std::vector<TopologyCell>().swap(found[c]);  // its pages back as the cells fill theirs
    }
  });
  begin_.pop_back();
  live_ = 0;
  for (int32_t t = 0; t < na; ++t) live_ += count_[t];
  TopologyStats stats;
  stats.triangles_searched = na;
  stats.pairs_tested = overlay.pairs_tested;
  stats.cells = live_;
  return stats;
}

TopologyStats OverlayTopology::Repair(const std::vector<Point2>& points_a,
                                      const Triangulation& mesh_a,
                                      const std::vector<Location>& a_in_b,
                                      const std::vector<Point2>& points_b,
                                      const Triangulation& mesh_b, const std::vector<int32_t>& dirty,
                                      const std::vector<std::pair<int32_t, int32_t>>& seeds,
                                      const Execution& execution, const uint8_t* keep_a,
                                      const uint8_t* keep_b) {
  const int32_t na = mesh_a.num_triangles();
  const int chunks = Chunks(na);
  if (static_cast<int>(fresh_.size()) < chunks) fresh_.resize(static_cast<std::size_t>(chunks));
  // Reads only the old topology; writes only its own searcher and chunk.
  auto repair = [&](Searcher& s, Fresh& out, int32_t lo, int32_t hi) {
    s.pb = &points_b;
    s.mb = &mesh_b;
    s.keep_b = keep_b;
    out.cells.clear();
    out.runs.clear();
    auto d = std::lower_bound(dirty.begin(), dirty.end(), lo);
    auto e = std::lower_bound(seeds.begin(), seeds.end(), std::make_pair(lo, -1));
    for (; d != dirty.end() && *d < hi; ++d) {
      const int32_t ta = *d;
      if (keep_a != nullptr && !keep_a[ta]) {  // junk: no cells, never searched
        out.runs.push_back({ta, static_cast<int64_t>(out.cells.size()), 0});
        continue;
      }
      const int32_t* va = &mesh_a.triangles[3 * ta];
      const Point2 a[3] = {points_a[va[0]], points_a[va[1]], points_a[va[2]]};
      s.Begin(a);
      for (int32_t k = 0; k < count_[ta]; ++k) s.Push(cells_of(ta)[k].triangle_b);
      for (int k = 0; k < 3; ++k) {
        if (a_in_b[va[k]].found()) s.Push(a_in_b[va[k]].triangle);
      }
      while (e != seeds.end() && e->first < ta) ++e;
      for (; e != seeds.end() && e->first == ta; ++e) s.Push(e->second);
      const int64_t first = static_cast<int64_t>(out.cells.size());
      if (!s.Run(&out.cells)) {
        // Nothing met from there: perhaps T_A only now reaches into B
        // across its hull; start from its neighbours' cells.
        for (int i = 0; i < 3; ++i) {
          const int32_t next = mesh_a.neighbors[3 * ta + i];
          if (next < 0) continue;
          for (int32_t k = 0; k < count_[next]; ++k) s.Push(cells_of(next)[k].triangle_b);
        }
        s.Run(&out.cells);
      }
      out.runs.push_back({ta, first, static_cast<int64_t>(out.cells.size()) - first});
    }
  };
  // The fresh cells come in T_A order, chunk after chunk, on any number of
  // threads. A chunk with no dirty triangle needs no searcher.
  ForEachChunk(execution, na, chunks, [&](int c, int64_t lo, int64_t hi) {
    Fresh& out = fresh_[c];
    out.stats = TopologyStats();
    const auto d = std::lower_bound(dirty.begin(), dirty.end(), static_cast<int32_t>(lo));
    if (d == dirty.end() || *d >= hi) {
      out.cells.clear();
      out.runs.clear();
      return;
    }
    std::unique_ptr<Searcher> searcher = Lend(mesh_b.num_triangles(), static_cast<int64_t>(points_b.size()));
    repair(*searcher, out, static_cast<int32_t>(lo), static_cast<int32_t>(hi));
    out.stats = searcher->stats;
    Return(std::move(searcher));
  });
  TopologyStats stats;
  for (int c = 0; c < chunks; ++c) {
    const Fresh& out = fresh_[c];
    const int64_t base = static_cast<int64_t>(cells_.size());
    cells_.insert(cells_.end(), out.cells.begin(), out.cells.end());
    for (const auto& run : out.runs) {
      live_ += run[2] - count_[run[0]];
      begin_[run[0]] = base + run[1];
      count_[run[0]] = static_cast<int32_t>(run[2]);
    }
    stats.triangles_searched += out.stats.triangles_searched;
    stats.pairs_tested += out.stats.pairs_tested;
  }
  if (static_cast<int64_t>(cells_.size()) > 2 * live_ + 4096) Compact();
  stats.cells = live_;
  return stats;
}

void OverlayTopology::Compact() {
  // Into the spare buffer and swapped: the two buffers keep their room, so
  // a long solve stops allocating (fresh pages fault in, one by one).
  UninitializedVector<TopologyCell>& packed = spare_;
  packed.clear();
  // Room for the appends until the next compaction (at 2 live + 4096 and
  // one repair's cells more): no reallocation, and so no copy, between.
  packed.reserve(static_cast<std::size_t>(live_ * 5 / 2 + 8192));
  for (std::size_t t = 0; t < begin_.size(); ++t) {
    const int64_t first = static_cast<int64_t>(packed.size());
    packed.insert(packed.end(), cells_.begin() + begin_[t], cells_.begin() + begin_[t] + count_[t]);
    begin_[t] = first;
  }
  cells_.swap(packed);
}

}  // namespace surfreg

#pragma once
// The overlay of A's mesh and B's moved mesh (measure/overlay.h) kept as
// combinatorics only, so that a re-measure after a small move recomputes the
// cells' corners from the current points instead of searching again.
//
// A cell is T_A ∩ T_B; each corner is an A vertex, a B vertex, or the
// crossing of an edge of T_A with an edge of T_B, named by local indices
// (one byte). Which pairs meet and which edges cross changes only when a
// vertex of one mesh crosses an edge of the other, i.e. when its location in
// the other mesh changes: the caller marks the A triangles near such
// vertices dirty and Repair searches only those again, with the same exact
// tests (separating axes on exact orientation signs) and the same clipping
// as the full overlay, so a repaired cell is the cell the full overlay makes.
//
// Storage: per A triangle a range of a flat cell array (cells of repaired
// triangles are appended; compacted when half the array is stale). No heap
// allocation per cell or per triangle once the buffers have grown.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "measure/tasks.h"
#include "measure/locator.h"
#include "measure/overlay_clip.h"
#include "measure/surface.h"
#include "measure/uninitialized_vector.h"

namespace surfreg {

// Corner codes (measure/overlay_clip.h): kind in bits 0-1, then the local
// indices; CornerCross(i, j) is T_A's edge i (opposite its vertex i) with
// T_B's edge j (opposite vertex j).
using overlay_internal::CornerA;
using overlay_internal::CornerB;
using overlay_internal::CornerCross;
using overlay_internal::kCornerA;
using overlay_internal::kCornerB;
using overlay_internal::kCornerCross;

// Trivial (no initializers), so that the topology's large array is filled
// by chunks without a zeroing pass first; TopologyCell{} is all zero.
struct TopologyCell {
  int32_t triangle_b;
  uint8_t num_corners;            // 3 to 6 (up to 8 in floating-point corner cases)
  std::array<uint8_t, 8> corner;  // counter-clockwise
};

// The corners of `cell` at the current points: `a` and `b` the corners of
// T_A and T_B, `ia` and `ib` their global vertex indices (a crossing is
// computed from its edges' endpoints in index order, so every cell sharing
// it gets the same point). Writes num_corners points to `out`.
inline void CellCorners(const TopologyCell& cell, const Point2 a[3], const int32_t ia[3],
                 const Point2 b[3], const int32_t ib[3], Point2* out) {
  for (int k = 0; k < cell.num_corners; ++k) {
    const uint8_t c = cell.corner[k];
    const int i = (c >> 2) & 3;
    switch (c & 3) {
      case kCornerA: out[k] = a[i]; break;
      case kCornerB: out[k] = b[i]; break;
      default: {
        const int j = (c >> 4) & 3;
        int p0 = (i + 1) % 3, p1 = (i + 2) % 3, q0 = (j + 1) % 3, q1 = (j + 2) % 3;
        if (ia[p0] > ia[p1]) std::swap(p0, p1);
        if (ib[q0] > ib[q1]) std::swap(q0, q1);
        const Point2& e0 = a[p0];
        const double ex = a[p1].x - e0.x, ey = a[p1].y - e0.y;
        const Point2& r = b[q0];
        const Point2& s = b[q1];
        const double vr = ex * (r.y - e0.y) - ey * (r.x - e0.x);
        const double vs = ex * (s.y - e0.y) - ey * (s.x - e0.x);
        const double denominator = vr - vs;
        double t = denominator != 0.0 ? vr / denominator : 0.5;
        t = std::min(1.0, std::max(0.0, t));
        out[k] = {r.x + t * (s.x - r.x), r.y + t * (s.y - r.y)};
      }
    }
  }
}

struct TopologyStats {
  int64_t triangles_searched = 0;  // A triangles searched (all of them on a build)
  int64_t pairs_tested = 0;        // (T_A, T_B) closure tests
  int64_t cells = 0;               // live cells after the call
};

class OverlayTopology {
 public:
  // The whole overlay (on the threads `execution` allows). Keeps no reference to
  // its arguments: each call passes the current meshes and points. Cells of
  // A triangles with keep_a[t] == 0 or B triangles with keep_b[t] == 0 (the
  // surfaces' junk, measure/domain.h) are not kept; the search still walks
  // through those B triangles. Null: keep all.
  TopologyStats Build(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                      const std::vector<Location>& a_in_b, const std::vector<Point2>& points_b,
                      const Triangulation& mesh_b, const std::vector<Location>& b_in_a,
                      const Execution& execution, const uint8_t* keep_a = nullptr,
                      const uint8_t* keep_b = nullptr);

  // Searches again the A triangles in `dirty` (ascending, unique). Each
  // search starts from the B triangles the triangle met before, from where
  // its vertices lie in B, and from `seeds` ((T_A, T_B) pairs known to meet,
  // ascending in T_A), then, if none of those meets it, from its
  // neighbours' cells. The meshes must be those of the last Build.
  TopologyStats Repair(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                       const std::vector<Location>& a_in_b, const std::vector<Point2>& points_b,
                       const Triangulation& mesh_b, const std::vector<int32_t>& dirty,
                       const std::vector<std::pair<int32_t, int32_t>>& seeds, const Execution& execution,
                       const uint8_t* keep_a = nullptr, const uint8_t* keep_b = nullptr);

  int32_t num_triangles_a() const { return static_cast<int32_t>(begin_.size()); }
  int64_t num_cells() const { return live_; }
  const TopologyCell* cells_of(int32_t ta) const { return cells_.data() + begin_[ta]; }
  int32_t count_of(int32_t ta) const { return count_[ta]; }
  // The same as plain arrays (cells_of(ta) = cells() + begins()[ta]), for
  // code that must not call inline functions (volume_kernel_body.h).
  const TopologyCell* cells() const { return cells_.data(); }
  const int64_t* begins() const { return begin_.data(); }
  const int32_t* counts() const { return count_.data(); }

  OverlayTopology();
  ~OverlayTopology();
  OverlayTopology(const OverlayTopology&) = delete;
  OverlayTopology& operator=(const OverlayTopology&) = delete;

 private:
  struct Searcher;  // a search's buffers, one per chunk running
  struct Fresh {    // a chunk's repaired cells
    std::vector<TopologyCell> cells;
    std::vector<std::array<int64_t, 3>> runs;  // (T_A, first, count) in `cells`
    TopologyStats stats;
  };
  void Compact();
  static int Chunks(int32_t num_a_triangles);
  std::unique_ptr<Searcher> Lend(int32_t num_b_triangles, int64_t num_b_points);
  void Return(std::unique_ptr<Searcher> searcher);

  std::mutex pool_mutex_;
  std::vector<std::unique_ptr<Searcher>> pool_;  // searchers not lent
  std::vector<Fresh> fresh_;                     // per chunk of Repair
  UninitializedVector<TopologyCell> cells_;
  UninitializedVector<TopologyCell> spare_;  // Compact's target: its room kept between calls
  std::vector<int64_t> begin_;  // per A triangle
  std::vector<int32_t> count_;  // per A triangle
  int64_t live_ = 0;
};

}  // namespace surfreg

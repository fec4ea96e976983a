#pragma once
// Internal to the tiled measure (tiled_measure.cc): a window of raster
// samples indexed by (column, row), its complete cells, and a tile's border
// edges. Not a public interface.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "measure/predicates.h"
#include "measure/surface.h"
#include "terrain/tiled_measure.h"
#include "terrain/tiled_partial.h"  // ConvexHull

namespace surfreg {
namespace tiled_internal {

// Sample index of each (column, row) of a window, -1 where nodata: the
// reader's surfaces are per window, so a dense table is tile-sized.
class WindowIndex {
 public:
  WindowIndex(const Surface& s, const SampleWindow& w) : w_(w) {
    index_.assign(static_cast<std::size_t>(w.columns) * w.rows, -1);
    for (std::size_t i = 0; i < s.raster_cell.size(); ++i) {
      const RasterCell& cell = s.raster_cell[i];
      if (!Inside(cell.column, cell.row)) {
        throw InputError(Name(s) + ": sample at cell (" + std::to_string(cell.column) + ", " +
                         std::to_string(cell.row) + ") outside the window read");
      }
      index_[Offset(cell.column, cell.row)] = static_cast<int32_t>(i);
    }
  }
  bool Inside(int32_t c, int32_t r) const {
    return c >= w_.column && c < w_.column + w_.columns && r >= w_.row && r < w_.row + w_.rows;
  }
  std::size_t Offset(int32_t c, int32_t r) const {
    return static_cast<std::size_t>(r - w_.row) * w_.columns + (c - w_.column);
  }
  int32_t At(int32_t c, int32_t r) const { return Inside(c, r) ? index_[Offset(c, r)] : -1; }
  // The four corners of cell (c, r) (samples (c, r) to (c+1, r+1)), or false.
  bool Corners(int32_t c, int32_t r, int32_t corner[4]) const {
    corner[0] = At(c, r), corner[1] = At(c + 1, r), corner[2] = At(c + 1, r + 1);
    corner[3] = At(c, r + 1);
    return corner[0] >= 0 && corner[1] >= 0 && corner[2] >= 0 && corner[3] >= 0;
  }
  static std::string Name(const Surface& s) {
    return s.source.empty() ? std::string("raster") : s.source;
  }

 private:
  SampleWindow w_;
  std::vector<int32_t> index_;
};

// The cells (c, r) with c in [c0, c1), r in [r0, r1) whose corners are all
// valid: their area (both grid triangles, grid_mesh.h) and their number.
inline double CompleteCellArea(const Surface& s, const WindowIndex& index, int32_t c0, int32_t c1,
                        int32_t r0, int32_t r1, int64_t* count) {
  double twice = 0.0;
  *count = 0;
  int32_t v[4];
  for (int32_t r = r0; r < r1; ++r) {
    for (int32_t c = c0; c < c1; ++c) {
      if (!index.Corners(c, r, v)) continue;
      const Point2 &p0 = s.xy[v[0]], &p1 = s.xy[v[1]], &p2 = s.xy[v[2]], &p3 = s.xy[v[3]];
      twice += std::fabs((p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x));
      twice += std::fabs((p2.x - p0.x) * (p3.y - p0.y) - (p2.y - p0.y) * (p3.x - p0.x));
      ++*count;
    }
  }
  return 0.5 * twice;
}

inline void MergeHull(const std::vector<Point2>& xy, std::vector<Point2>* hull) {
  std::vector<Point2> points = *hull;
  points.insert(points.end(), xy.begin(), xy.end());
  *hull = ConvexHull(std::move(points));
}

// The edges of a tile's reference samples along its block's border (both
// ends valid), bucketed so that a point finds the few it may lie on.
class TileBorder {
 public:
  TileBorder(const Surface& a, const WindowIndex& index, const SampleWindow& w) {
    const int32_t c0 = w.column, c1 = w.column + w.columns - 1;
    const int32_t r0 = w.row, r1 = w.row + w.rows - 1;
    auto add = [&](int32_t ca, int32_t ra, int32_t cb, int32_t rb) {
      const int32_t u = index.At(ca, ra), v = index.At(cb, rb);
      if (u >= 0 && v >= 0) edges_.push_back({a.xy[u], a.xy[v]});
    };
    for (int32_t r = r0; r < r1; ++r) add(c0, r, c0, r + 1), add(c1, r, c1, r + 1);
    for (int32_t c = c0; c < c1; ++c) add(c, r0, c + 1, r0), add(c, r1, c + 1, r1);
    lo_ = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    Point2 hi{-lo_.x, -lo_.y};
    for (const auto& e : edges_) {
      for (const Point2& p : e) {
        lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
      }
    }
    buckets_ = std::max(1, std::max(w.columns, w.rows));
    step_ = {(hi.x - lo_.x) / buckets_, (hi.y - lo_.y) / buckets_};
    if (!(step_.x > 0.0)) step_.x = 1.0;
    if (!(step_.y > 0.0)) step_.y = 1.0;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const auto& s = edges_[e];
      const int bx0 = Bucket(std::min(s[0].x, s[1].x), lo_.x, step_.x);
      const int bx1 = Bucket(std::max(s[0].x, s[1].x), lo_.x, step_.x);
      const int by0 = Bucket(std::min(s[0].y, s[1].y), lo_.y, step_.y);
      const int by1 = Bucket(std::max(s[0].y, s[1].y), lo_.y, step_.y);
      for (int by = by0; by <= by1; ++by) {
        for (int bx = bx0; bx <= bx1; ++bx) grid_[Key(bx, by)].push_back(static_cast<int32_t>(e));
      }
    }
  }

  // p lies on one of the edges (exact). The bucket of a coordinate is
  // monotone in it, so an edge's buckets hold every point of its box.
  bool Holds(const Point2& p) const {
    if (edges_.empty()) return false;
    const auto it = grid_.find(Key(Bucket(p.x, lo_.x, step_.x), Bucket(p.y, lo_.y, step_.y)));
    if (it == grid_.end()) return false;
    for (int32_t e : it->second) {
      const Point2 &s0 = edges_[e][0], &s1 = edges_[e][1];
      if (std::min(s0.x, s1.x) <= p.x && p.x <= std::max(s0.x, s1.x) &&
          std::min(s0.y, s1.y) <= p.y && p.y <= std::max(s0.y, s1.y) && Orient2D(s0, s1, p) == 0.0) {
        return true;
      }
    }
    return false;
  }

 private:
  int Bucket(double v, double lo, double step) const {
    const double b = std::floor((v - lo) / step);
    return static_cast<int>(std::min(std::max(b, 0.0), static_cast<double>(buckets_ - 1)));
  }
  int64_t Key(int bx, int by) const { return static_cast<int64_t>(by) * buckets_ + bx; }

  std::vector<std::array<Point2, 2>> edges_;
  std::unordered_map<int64_t, std::vector<int32_t>> grid_;
  Point2 lo_, step_;
  int buckets_ = 1;
};

}  // namespace tiled_internal
}  // namespace surfreg

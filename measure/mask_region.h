#pragma once
// The mask of WeightMode::kMask: μ = 1 on a region given by rings (simple
// closed polygons) combined by the even–odd rule, 0 elsewhere. A point is in
// the region when it is inside an odd number of rings, or on any ring: a
// ring inside another is a hole, an island in a hole is in again. Rings must
// not cross or touch each other, so every ring lies inside a nested chain of
// others and its depth (how many contain it) is well defined.
//
// Integrals over the region are sums over signed triangles: each ring is cut
// into triangles (ear clipping), with sign +1 at even depth and −1 at odd
// depth; Σ sign × ∫(cell ∩ triangle) is exact up to rounding. A uniform grid
// of buckets over the triangles' bounding boxes finds the few triangles that
// meet a cell, and horizontal strips of edges answer the point test, so a
// mask of thousands of vertices costs about as much per query as a square.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "measure/surface.h"

namespace surfreg {

// One ring in input coordinates: either orientation, not closed explicitly.
using MaskRing = std::vector<std::array<double, 2>>;

// Include: μ = 1 on the region (stable terrain). Exclude: μ = 1 outside it
// (the rings are unstable areas); done by one more ring around everything.
enum class MaskMode { kInclude, kExclude };
const char* MaskModeName(MaskMode mode);  // "include" | "exclude"

struct MaskRegion {
  std::vector<std::vector<Point2>> rings;        // local frame
  std::vector<int> depth;                        // per ring: rings containing it
  std::vector<std::array<Point2, 3>> triangles;  // counter-clockwise, of every ring
  std::vector<double> sign;                      // per triangle: +1 or −1

  // Triangle buckets: columns × rows cells of size cell over [lo, ...),
  // CSR (bucket b holds bucket_items[bucket_start[b] .. bucket_start[b+1])).
  Point2 lo{0, 0}, hi{0, 0};
  double cell_x = 1, cell_y = 1;
  int columns = 0, rows = 0;
  std::vector<int32_t> bucket_start, bucket_items;
  std::vector<std::array<int32_t, 2>> first_bucket;  // per triangle: lowest column, row

  // Edge strips for the point test: every edge whose y-range meets strip s
  // is in strip_items[strip_start[s] .. strip_start[s+1]).
  double strip_y0 = 0, strip_h = 1;
  int strips = 0;
  std::vector<int32_t> strip_start, strip_items;
  std::vector<std::array<Point2, 2>> edges;

  bool empty() const { return rings.empty(); }
  int Column(double x) const;
  int Row(double y) const;
};

// Checks rings in input coordinates: each has ≥ 3 finite vertices and non-zero
// area and is simple; no two rings share a point. On failure, *error names
// the ring(s) by `name` (ring index → e.g. "ring 2" or "feature 7 ring 1").
bool ValidMaskRings(const std::vector<MaskRing>& rings,
                    const std::function<std::string(std::size_t)>& name, std::string* error);
// The same with rings named "mask ring k" (1-based), or "mask polygon" for one.
bool ValidMaskRings(const std::vector<MaskRing>& rings, std::string* error);

// Builds the region of valid rings, moved into the local frame whose origin
// is `origin` (input coordinates). With kExclude, `cover` (local points, e.g.
// the reference's samples) must lie inside the added enclosing ring.
MaskRegion MakeMaskRegion(const std::vector<MaskRing>& rings, MaskMode mode,
                          const std::array<double, 2>& origin,
                          const std::vector<Point2>& cover = {});

// Whether p (local frame) is in the region (even–odd, boundary in; exact).
bool InsideMask(const MaskRegion& mask, const Point2& p);

// Calls f(k) once for every triangle k whose bounding box meets the box
// [lo, hi] (a superset of the triangles meeting it).
template <typename F>
void ForEachMaskTriangle(const MaskRegion& mask, const Point2& lo, const Point2& hi, F&& f) {
  if (mask.columns == 0 || hi.x < mask.lo.x || hi.y < mask.lo.y || lo.x > mask.hi.x ||
      lo.y > mask.hi.y) {
    return;
  }
  const int c0 = mask.Column(lo.x), c1 = mask.Column(hi.x);
  const int r0 = mask.Row(lo.y), r1 = mask.Row(hi.y);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const int b = r * mask.columns + c;
      for (int32_t i = mask.bucket_start[b]; i < mask.bucket_start[b + 1]; ++i) {
        const int32_t k = mask.bucket_items[i];
        // A triangle in several of these buckets: only its first one counts.
        const auto& first = mask.first_bucket[k];
        if (c != std::max(c0, first[0]) || r != std::max(r0, first[1])) continue;
        f(k);
      }
    }
  }
}

// A simple polygon's triangles (3 points each, counter-clockwise).
std::vector<std::array<Point2, 3>> TriangulatePolygon(std::vector<Point2> polygon);

// Whether p is inside or on the boundary of one simple polygon (exact).
bool InsidePolygon(const std::vector<Point2>& polygon, const Point2& p);

}  // namespace surfreg

#pragma once
// Internals of delaunay.cc shared with delaunay_slabs.cc and their tests:
// the incremental build on one thread, and the build of large inputs in
// vertical slabs stitched along their seams.
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"

namespace surfreg {
namespace delaunay_internal {

// Whether the circle through a, b, c lies strictly between x = lo and x = hi,
// decided conservatively (false when unsure).
bool CircleWithin(const Point2& a, const Point2& b, const Point2& c, double lo, double hi);

// The incremental build on the calling thread (options.execution ignored).
Triangulation TriangulateOneThread(const std::vector<Point2>& points,
                                   const DelaunayOptions& options);

// A slab's share of the whole (delaunay_slabs.cc): its triangles whose
// circle lies strictly between the neighbouring slabs (CircleWithin), "final",
// numbered in TriangulateOneThread's order with the others left out; what
// the stitch needs of the rest. Built straight from the incremental build
// while it is in cache: no whole mesh of the slab.
struct SlabPart {
  struct Edge {
    int32_t from, to;        // input indices
    int32_t triangle, edge;  // final triangle and its edge from -> to
  };
  std::vector<int32_t> triangles;    // final ones, corners as input indices
  std::vector<int32_t> neighbors;    // final index; -1 across the frontier
  std::vector<Edge> frontier;        // final triangles' edges to a non-final one or the hull
  std::vector<int32_t> first_final;  // per slab point: its lowest final triangle, or -1
  std::vector<int32_t> seam;         // input indices of the stitch's vertices, increasing
  std::vector<int32_t> kept;         // with duplicates: per slab point, the input index kept
  int32_t num_final = 0;
  int32_t num_duplicates = 0;
};

// The slab's part, `points` being the input points input[0], input[1], ...
// (increasing) and lo, hi the neighbouring slabs' nearest x. Throws
// InputError as TriangulateOneThread does.
void TriangulateSlab(const std::vector<Point2>& points, const std::vector<int32_t>& input,
                     const DelaunayOptions& options, double lo, double hi, SlabPart* part);

// The build in x-slabs of about `slab_points` points each (their number a
// function of the input's size only, so that the arrays are the same on any
// number of threads), one task each on options.execution, stitched by
// triangulating the vertices near the seams. Returns false (and leaves
// *out alone) when the input is smaller than two slabs or does not split
// (few distinct x, a collinear slab, no triangle clear of the seams): the
// caller then builds on one thread.
constexpr int64_t kSlabPoints = 100000;
bool TriangulateInSlabs(const std::vector<Point2>& points, const DelaunayOptions& options,
                        Triangulation* out, int64_t slab_points = kSlabPoints);

}  // namespace delaunay_internal
}  // namespace surfreg

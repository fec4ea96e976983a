#pragma once
// Internals of delaunay.cc shared with delaunay_slabs.cc and their tests:
// the incremental build on one thread, and the build of large inputs in
// vertical slabs stitched along their seams.
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"

namespace surfreg {
namespace delaunay_internal {

// The incremental build on the calling thread (options.execution ignored).
Triangulation TriangulateOneThread(const std::vector<Point2>& points,
                                   const DelaunayOptions& options);

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

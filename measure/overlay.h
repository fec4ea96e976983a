#pragma once
// The common refinement (overlay) of two triangulations A and B over
// Ω = Conv(A) ∩ Conv(B): every convex polygon T_A ∩ T_B of positive area.
// Both piecewise-linear surfaces are linear on each cell, so integrals of
// their gap over the cells are exact (docs/method.md, How a comparison runs).
//
// How: for each triangle T_A, a breadth-first search over the triangles of B
// whose closures meet T_A, decided exactly (separating-axis tests with exact
// orientation signs), each pair clipped into a cell. Searches start from
// where A's vertices were located in B (and B's in A), and hand their
// results across A's edges to the neighbouring triangles, so the work is
// O(N_A + N_B + K), K the number of edge crossings. Cell corners that are
// edge crossings are computed in floating point (they never decide topology).
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "measure/delaunay.h"
#include "measure/locator.h"
#include "measure/surface.h"

namespace surfreg {

struct OverlayCell {
  int32_t triangle_a = -1;
  int32_t triangle_b = -1;
  int num_vertices = 0;                // 3 to 6: a triangle clipped by a triangle
  std::array<Point2, 8> vertices;      // convex, counter-clockwise
  double area = 0.0;                   // > 0
};

struct OverlayStats {
  int64_t cells = 0;         // cells of positive area visited
  int64_t pairs_tested = 0;  // (T_A, T_B) closure-intersection tests
};

// Visits every cell of positive area once. `a_in_b[i]` is the location of A's
// point i in B (LocateAll), `b_in_a` likewise; both index like the points.
OverlayStats ForEachOverlayCell(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                                const std::vector<Location>& a_in_b,
                                const std::vector<Point2>& points_b, const Triangulation& mesh_b,
                                const std::vector<Location>& b_in_a,
                                const std::function<void(const OverlayCell&)>& visit);

// The same cells, in two halves of A's triangles (by index: spatially
// coherent halves), then the few triangles reached only across the boundary.
// With `parallel` the second half runs on another thread; without, after the
// first. Either way `visit_second` sees the second half's cells and
// `visit_first` the others, each in the same order: which cells each sees and
// in which order depends only on the input, never on timing or the thread
// count, so sums made per visitor and added first + second are the same bits
// on one thread as on two. `visit_first` is called from the calling thread
// only and `visit_second` from one thread only, so each may accumulate
// without locks.
OverlayStats ForEachOverlayCellInTwo(const std::vector<Point2>& points_a,
                                     const Triangulation& mesh_a,
                                     const std::vector<Location>& a_in_b,
                                     const std::vector<Point2>& points_b,
                                     const Triangulation& mesh_b,
                                     const std::vector<Location>& b_in_a,
                                     const std::function<void(const OverlayCell&)>& visit_first,
                                     const std::function<void(const OverlayCell&)>& visit_second,
                                     bool parallel = true);

}  // namespace surfreg

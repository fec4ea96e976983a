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
#include "measure/tasks.h"

namespace surfreg {

struct OverlayCell {
  int32_t triangle_a = -1;
  int32_t triangle_b = -1;
  int num_vertices = 0;                // 3 to 6: a triangle clipped by a triangle
  std::array<Point2, 8> vertices;      // convex, counter-clockwise
  double area = 0.0;                   // > 0
  // Only when asked for (ForEachOverlayCellInChunks' `labelled`): what each
  // corner is, a vertex of T_A or T_B or the crossing of two of their edges
  // (measure/overlay_clip.h's codes).
  std::array<uint8_t, 8> labels{};
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

// The same cells, from `chunks` fixed ranges of A's triangles (by index:
// spatially coherent ranges) searched side by side, then the few triangles
// reached only across the ranges' boundaries. visit(c, cell) sees chunk c's
// cells, the last ones as chunk 0's: which cells each chunk sees and in which
// order depends only on the input and `chunks`, never on timing or the
// thread count, so sums made per chunk and added in chunk order are the same
// bits on any number of threads. Calls for one chunk come from one thread
// at a time, so a visitor per chunk may accumulate without locks.
// `labelled`: the cells' corner labels too (the kept overlay's).
OverlayStats ForEachOverlayCellInChunks(const std::vector<Point2>& points_a, const Triangulation& mesh_a,
                                        const std::vector<Location>& a_in_b,
                                        const std::vector<Point2>& points_b, const Triangulation& mesh_b,
                                        const std::vector<Location>& b_in_a, int chunks,
                                        const std::function<void(int chunk, const OverlayCell&)>& visit,
                                        const Execution& execution, bool labelled = false);

// The chunk count for A's mesh: a function of its size only.
int OverlayChunks(const Triangulation& mesh_a);

}  // namespace surfreg

#pragma once
// 2D Delaunay triangulation of a surface's xy projection, as flat arrays made
// for walking.
//
// Exactness: orientation and in-circle decisions use the exact predicates of
// predicates.h; cocircular ties use InCirclePerturbed, so the triangulation
// is unique for a given point set (independent of input order) even on grids.
// Every distinct input point is a vertex, including collinear points on the
// convex hull.
//
// Duplicates: points with identical (x, y) are merged. The vertex keeps the
// lowest input index of its group; the others are not referenced by any
// triangle and `vertex_of_input` maps them to the kept index. Heights are
// not touched here (the mesh layer decides how to merge z).
#include <cstdint>
#include <vector>

#include "measure/surface.h"
#include "measure/tasks.h"

namespace surfreg {

struct Triangulation {
  // Vertex indices of each triangle, counter-clockwise: triangle t has
  // vertices triangles[3t], triangles[3t+1], triangles[3t+2], indices into
  // the input point array.
  std::vector<int32_t> triangles;
  // neighbors[3t+i]: the triangle across the edge opposite vertex i (the edge
  // from vertex i+1 to vertex i+2, indices mod 3), or -1 on the convex hull.
  std::vector<int32_t> neighbors;
  // vertex_triangle[v]: one triangle incident to vertex v, -1 for merged
  // duplicates (a walk can start there).
  std::vector<int32_t> vertex_triangle;
  // vertex_of_input[i]: the vertex that input point i became (i itself,
  // unless i is a merged duplicate).
  std::vector<int32_t> vertex_of_input;
  int32_t num_duplicates = 0;  // input points merged into an earlier one

  int32_t num_triangles() const { return static_cast<int32_t>(triangles.size() / 3); }
};

struct DelaunayOptions {
  // Insertion order: biased randomized insertion order (BRIO) rounds, each
  // sorted along a Hilbert curve. Only speed depends on it, never the result.
  bool spatial_sort = true;
  uint64_t seed = 0x5eedULL;  // for the BRIO rounds; result does not depend on it
  // Large inputs on several threads are built in vertical slabs side by
  // side and stitched along the seams. The arrays are the same to the bit
  // on any number of threads: the triangulation is unique and numbered
  // canonically (by lowest vertex, then the next one counter-clockwise).
  Execution execution;
};

// Triangulates `points` (relative coordinates, see Surface). Throws
// InputError if fewer than 3 distinct points or all points are collinear.
Triangulation Triangulate(const std::vector<Point2>& points,
                          const DelaunayOptions& options = DelaunayOptions());

// The area covered by the mesh's triangles (the convex hull's area for a
// Delaunay triangulation; signed sum, so folded triangles subtract).
double MeshArea(const std::vector<Point2>& points, const Triangulation& mesh);

}  // namespace surfreg

#pragma once
// Euclidean minimum spanning tree of a point set, from its Delaunay
// triangulation (the EMST is a subgraph of it), and the tree's depth-first
// order. Locating a cloud in another surface's mesh point by point in this
// order lets every walk start where its tree neighbour was found, so walks
// are short (Dyshkant 2010, 2.2.2).
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "measure/tasks.h"

namespace surfreg {

struct SpanningTree {
  // Every vertex of the triangulation once, each tree visited depth first
  // from its root (one tree per connected component; one in all for a
  // triangulation). Merged duplicates are not listed.
  std::vector<int32_t> order;
  // parent[v]: v's neighbour towards the root; -1 for a root and for merged
  // duplicates. Indexed like the input points.
  std::vector<int32_t> parent;
  double total_length = 0.0;  // sum of edge lengths, data units
};

// Kruskal's algorithm over the triangulation's edges (radix-sorted by exact
// squared length, ties by edge position), so O(N) besides the sort's passes.
// The edges' gathering and sort run in chunks on `execution`; the tree is
// the same on any number of threads.
SpanningTree EuclideanMst(const std::vector<Point2>& points, const Triangulation& mesh,
                          const Execution& execution = Execution());

}  // namespace surfreg

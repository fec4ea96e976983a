#pragma once
// Re-meshing a moved surface around the triangles it keeps, locally.
//
// A fixed surface (PairState::FixSurface) keeps its data triangles R; the
// rest of its mesh only makes the mesh cover the convex hull for walking.
// When a tilt turns some of that filler over (hull slivers fold at any
// tilt), the filler must be rebuilt. Only R's boundary decides it: the
// Delaunay triangulation of the vertices of the triangles that touch R's
// boundary (a few per cent of the points), with those triangles forced in
// (measure/enforce_triangles.h), gives the filler as its triangles outside
// R; R's triangles keep their adjacency from the current mesh. At 1e5
// points this replaced a Delaunay triangulation of every vertex.
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"

namespace surfreg {

// `current`: a triangulation of `points` in which the triangles flagged in
// `keep` (per triangle of `current`) are faces and counter-clockwise at
// `points`; its other triangles may be folded. On success `out` is a valid
// triangulation (counter-clockwise, consistent neighbors) of the vertices of
// the kept triangles, covering their convex hull and holding every kept
// triangle, first and in `current`'s order; the other points belong to no
// triangle (vertex_triangle −1). False (with `out` unspecified) when that
// cannot be done this way (two kept vertices at the same xy, or a kept
// triangle that another kept vertex lies in): the caller re-triangulates
// whole.
bool RemeshAroundKept(const std::vector<Point2>& points, const Triangulation& current,
                      const std::vector<uint8_t>& keep, Triangulation* out);

// The whole re-mesh behind RemeshAroundKept: the Delaunay triangulation of
// every vertex of `triangles` (3 indices each into `points`), with those
// triangles forced in; indexed like `points`, the other points belong to no
// triangle. False when they cannot all be faces (EnforceTriangles refused).
bool TriangulateKept(const std::vector<Point2>& points, const std::vector<int32_t>& triangles,
                     Triangulation* out);

}  // namespace surfreg

#pragma once
// Forcing given triangles into a triangulation by edge flips.
//
// Use: a moved surface keeps a fixed set of "domain" triangles (its real
// data); the rest of its mesh may be re-triangulated freely. Re-triangulating
// means Delaunay of the moved xy, then putting every domain triangle back,
// which is what EnforceTriangles does. At a slightly different pose only a
// handful of domain triangles are missing, so the cost is dominated by
// checking each required triangle once (a walk around one vertex's fan); only
// the missing ones cost more (their edges are checked, then recovered).
//
// Method: Sloan's edge recovery (Sloan 1993, "A fast algorithm for generating
// constrained Delaunay triangulations"): for a missing edge uv, collect the
// edges that cross segment uv by walking from u along it, then flip them one
// at a time in queue order, skipping (and requeueing) those whose
// quadrilateral is not strictly convex; a flipped edge that still crosses uv
// goes back on the queue. Required edges are never flipped (an edge that
// crosses another required edge means two required triangles overlap), so
// recovering one edge cannot lose an earlier one. No Delaunay restoration
// afterwards: triangles that are not required may be any shape.
//
// Exactness: every decision (which wedge of u's fan the segment leaves by,
// which edge the walk crosses, whether a vertex is on the segment, whether a
// quadrilateral is strictly convex) is an exact orientation sign
// (predicates.h), so collinear and cocircular input (grids) is handled and
// the mesh stays a valid triangulation whatever the answer.
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"

namespace surfreg {

// Makes `mesh`, a valid triangulation of `points` (every non-duplicate vertex
// used, all triangles counter-clockwise, neighbors consistent), contain every
// triangle of `required` (3 vertex indices per triangle, any rotation of the
// triple) by edge flips. Triangles that are not required may change
// arbitrarily; neighbors and vertex_triangle stay consistent.
//
// Returns true when every required triangle is a face of `mesh` afterwards.
// Returns false when that is impossible: a required triangle is not
// counter-clockwise at `points` (or is degenerate, or names a merged
// duplicate or an index out of range), contains another vertex (inside or on
// an edge), or two required triangles overlap. The mesh is then still a valid
// triangulation; the required triangles that could be enforced are, as far
// as the failures allow (no guarantee which). Also false, never a hang, if an
// edge's recovery exceeds its flip budget (a safety cap far above what any
// valid input was seen to need; see the .cc).
//
// Throws std::invalid_argument when required.size() is not a multiple of 3 or
// mesh->vertex_triangle.size() != points.size() (caller errors).
bool EnforceTriangles(const std::vector<Point2>& points, const std::vector<int32_t>& required,
                      Triangulation* mesh);

}  // namespace surfreg

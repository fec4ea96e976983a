#pragma once
// Point location in a triangulation by straight-line walking (Dyshkant 2010,
// 2.2.1): from a vertex of a known triangle, follow the segment to the query
// point across the triangles it meets; where the segment passes exactly
// through a vertex, turn around that vertex to the triangle it continues in.
// All decisions use exact orientation tests, so the walk is correct on
// collinear and cocircular input (grids) and terminates on any valid
// triangulation, Delaunay or not (a moved surface keeps its own mesh).
#include <array>
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/spanning_tree.h"
#include "measure/tasks.h"
#include "measure/surface.h"

namespace surfreg {

enum class Where : uint8_t {
  kInside,    // strictly inside `triangle`
  kOnEdge,    // on edge `index` (opposite local vertex `index`) of `triangle`
  kOnVertex,  // at local vertex `index` of `triangle`
  kOutside,   // outside the convex hull; `triangle` and hull edge `index` are
              // where the walk left the mesh (a good start for nearby points)
};

struct Location {
  int32_t triangle = -1;
  Where where = Where::kOutside;
  int8_t index = -1;
  // Barycentric coordinates of the point in `triangle` (sum 1; exact 0 on
  // the edges that hold it, exact 1 at a vertex). Undefined when outside.
  std::array<double, 3> barycentric = {0.0, 0.0, 0.0};

  bool found() const { return where != Where::kOutside; }
};

// The piecewise-linear interpolant of per-vertex `values` at a found
// location (location.found() must hold).
inline double InterpolateAt(const Triangulation& mesh, const std::vector<double>& values,
                            const Location& location) {
  const int32_t* v = &mesh.triangles[3 * location.triangle];
  return location.barycentric[0] * values[v[0]] + location.barycentric[1] * values[v[1]] +
         location.barycentric[2] * values[v[2]];
}

// The same interpolant at p (located at `location`, found), to the last bit
// whatever the mesh: corners taken in an order fixed by their coordinates,
// and a point on an edge from that edge's two ends alone (either triangle
// beside it). InterpolateAt's barycentric coordinates depend on which corner
// a mesh lists first and, on an edge, on the third corner, so a window's mesh
// and the whole raster's gave dz differing in the last bit (tiled_measure.h).
double InterpolateCanonical(const std::vector<Point2>& points, const Triangulation& mesh,
                            const std::vector<double>& values, const Location& location,
                            const Point2& p);

// The most triangles a walk may visit before LocatePoint gives up: 4 per
// triangle + 64. On a valid mesh no walk comes near it: the segment from the
// start vertex to p crosses each triangle at most once (T steps), and the
// turns around the vertices on that segment visit each vertex's fan at most
// once in each sense; no triangle has 3 vertices on one segment, so the fans
// add at most 2T, plus one step per vertex on the segment (fewer than T + 3).
// Only corrupted adjacency (e.g. neighbors that form a cycle) can reach it.
int64_t WalkStepLimit(const Triangulation& mesh);

// Locates p in `mesh` (vertex positions `points`), walking from
// `start_triangle` (any triangle; nearer is faster). `steps`, if given,
// receives the number of triangles visited. A walk that exceeds
// WalkStepLimit(mesh) (an invalid mesh: a broken internal invariant, never
// bad user input) throws std::logic_error "internal error: ..." instead of
// looping; the CLI reports it with exit code 1.
Location LocatePoint(const std::vector<Point2>& points, const Triangulation& mesh, const Point2& p,
                     int32_t start_triangle, int* steps = nullptr);

// Locates the exact centroid g = (corners[0] + corners[1] + corners[2]) / 3
// of three points without rounding it to a double (Orient2DCentroidSign):
// kOnEdge / kOnVertex exactly when g lies on an edge / at a vertex of the
// mesh. A rounded g lands on either side of an edge it lies on, depending on
// the frame (a translation by whole units changes the rounding); this answer
// does not. Walks from `start_triangle` by visibility (on each triangle,
// across an edge that g lies strictly beyond) and, should a non-Delaunay
// mesh make that cycle past WalkStepLimit, checks every triangle.
// `barycentric` holds the rounded centroid's coordinates in the triangle
// found (clamped to it; exact 0 on the edges that hold g).
Location LocateCentroid(const std::vector<Point2>& points, const Triangulation& mesh,
                        const std::array<Point2, 3>& corners, int32_t start_triangle);

// Same, checking every triangle: the oracle for tests. O(number of triangles).
Location LocatePointBruteForce(const std::vector<Point2>& points, const Triangulation& mesh,
                               const Point2& p);

struct LocateAllStats {
  int64_t steps = 0;  // triangles visited by all walks together
};

// Locates every query point (e.g. the other surface's samples), visiting them
// in the order of `query_tree` (the queries' own EMST) so that each walk
// starts from the triangle where its tree parent was found. Merged
// duplicates among the queries (query_mesh.vertex_of_input) take their kept
// point's location. Result indexed like `queries`. Large query sets walk in
// chunks of the tree order on `execution`: a chunk's first walk starts
// where the previous chunk's first point was found (found in turn before),
// a point whose parent is in an earlier chunk from the point before it. The
// result is the same on any number of threads.
std::vector<Location> LocateAll(const std::vector<Point2>& points, const Triangulation& mesh,
                                const std::vector<Point2>& queries,
                                const Triangulation& query_mesh, const SpanningTree& query_tree,
                                LocateAllStats* stats = nullptr,
                                const Execution& execution = Execution());

}  // namespace surfreg

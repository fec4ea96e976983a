#pragma once
// The data domain of a sampled surface: the triangles of its mesh (Delaunay,
// or a raster's grid mesh) that are data, not the convex hull's filler (issue 20).
//
// A convex-hull triangulation bridges every gap: voids in a DEM, the concave
// outline of a face patch, and the thin slivers that join nearly collinear
// samples along the hull. Those triangles are not measured surface: their
// heights are invented, and the slivers stand nearly vertical in 3D, so a
// tilt of a fraction of a degree turns them over. The data domain drops them:
//
// - scattered samples: a triangle whose longest edge is longer than
//   `max_edge_spacings` times the local sample spacing (the largest over its
//   three vertices; a vertex's is the lower quartile, over its Delaunay
//   neighbours, of each neighbour's median edge length: robust to the long
//   edges of a void's rim, and right for anisotropic scan lines)
//   bridges a gap; then, from the outside in, a triangle on the domain's
//   boundary thinner than `min_boundary_thinness` (its height over its
//   longest edge, divided by that edge; 0.866 for an equilateral triangle)
//   is an outline sliver, and is peeled, until no boundary triangle is one;
// - raster samples (`grid`): the mesh holds the raster's cells, each split
//   by one diagonal rule (grid_mesh.h); the domain is exactly those grid
//   triangles. A cell with a nodata corner is not part of the surface.
//
// Thresholds (measured, docs/align.md, "The data domain"): on rectangular crops of
// the benchmark's face and LIDAR clouds they keep 98.9% and 99.0% of the
// hull's area, on scan lines 0.4 apart along and 2 across 99.7%; a void of
// area 707 in 2500 random samples over 100 × 100 leaves out 923 (the void
// and its ragged rim).
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "measure/tasks.h"

namespace surfreg {

struct Location;  // measure/locator.h

enum class DomainKind {
  kData,  // the data domain (default)
  kHull,  // the paper's: the whole convex hull
};

struct DomainRule {
  DomainKind kind = DomainKind::kData;
  double max_edge_spacings = 4.0;
  double min_boundary_thinness = 0.1;
  bool grid = false;  // the samples are one raster's (Surface::raster_cell)
};

// Per triangle of `mesh` (a triangulation of `xy`): 1 if it is part of the
// data domain, 0 if not. kHull: all 1. With rule.grid (and kData) the domain
// is `grid`, the grid triangles EnforceGrid reported for this mesh; then
// `grid` is required (std::invalid_argument if null or of the wrong size).
// The per-vertex and per-triangle work runs in chunks on `execution`'s
// threads: the same domain on any number.
std::vector<uint8_t> DataDomain(const std::vector<Point2>& xy, const Triangulation& mesh,
                                const DomainRule& rule = DomainRule(),
                                const std::vector<uint8_t>* grid = nullptr,
                                const Execution& execution = Execution{1});

// The xy area of the triangles with in_domain[t] != 0.
double DomainArea(const std::vector<Point2>& xy, const Triangulation& mesh,
                  const std::vector<uint8_t>& in_domain);

// Per vertex: 1 if the vertex is a corner of some triangle in the domain.
std::vector<uint8_t> DomainVertices(const Triangulation& mesh, std::size_t num_vertices,
                                    const std::vector<uint8_t>& in_domain);

// Per vertex: 1 if every triangle around it is in the domain and it is not
// on the hull (an inner vertex of the domain), 0 if it is on the domain's
// outline or outside it. Interpolated linearly, these make a taper that is 1
// inside the domain's outer ring of triangles and falls to 0 on its outline.
std::vector<uint8_t> InteriorVertices(const Triangulation& mesh, std::size_t num_vertices,
                                      const std::vector<uint8_t>& in_domain);

const char* DomainKindName(DomainKind kind);  // "data" | "hull"

// One surface's domain as the measures use it.
struct MeshDomain {
  std::vector<uint8_t> triangles;  // DataDomain
  std::vector<uint8_t> vertices;   // DomainVertices
  double area = 0;                 // DomainArea
  bool whole = true;               // every triangle is in (no test needed)

  // Whether a point located in the mesh (LocatePoint) lies in the closed
  // domain: inside a domain triangle; on an edge of one (either triangle
  // sharing the edge); at a vertex of one.
  bool Contains(const Triangulation& mesh, const Location& location) const;
};

MeshDomain MakeMeshDomain(const std::vector<Point2>& xy, const Triangulation& mesh,
                          const DomainRule& rule, const std::vector<uint8_t>* grid = nullptr,
                          const Execution& execution = Execution{1});

}  // namespace surfreg

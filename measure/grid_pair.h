#pragma once
// Two rasters sampling one grid, or one lattice offset by a fraction of a
// cell (issue 47): the measure from the grids' own cells, without a
// triangulation, a spanning tree, walks or the general overlay. Internal,
// for measures.cc (grid_pair.cc, grid_sweep.cc).
//
// When both surfaces' samples lie on one lattice (each surface's positions
// an affine function of its cells, the two the same function up to a
// whole-cell offset, and every position both have exactly equal), both
// meshes are the grid's cells split by the one rule (grid_mesh.h), so their
// overlay is the cells both have whole, and each cell's two triangles carry
// d = F̂_B − F̂_A as one linear function: integrated in closed form by the
// general overlay's own cell integrator (gap_volume.h, IntegrateConvex).
// The result is the general path's to rounding (the same cells, summed in
// another order).
#include <array>
#include <cstdint>
#include <vector>

#include "measure/gap_volume.h"
#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg {

struct GridPairResult {
  VolumeResult volume;  // over Ω: the cells complete in both
  double hull_area_a = 0, hull_area_b = 0;      // convex hulls of the samples
  double domain_area_a = 0, domain_area_b = 0;  // the complete cells' areas
  double rho_d_axial = 0;                       // mean |d| at Ω's nodes (weighted by μ)
  int64_t n_overlap_nodes = 0;
  // With keep_node_gaps, in A's input order (as MeasureSummary's): d at
  // A's nodes in Ω (NaN elsewhere) and each node's share of the area.
  std::vector<double> dz_a, node_area_a;
  // d at B's nodes in Ω that are not A's (MeasureSummary::dz_b); empty when
  // every such node is one of A's (one grid).
  std::vector<double> dz_b;
};

// True, with *out filled, if A and B are rasters on one grid as above and
// `options` are ones this path computes exactly (overlay volume, the data
// domain, uniform or mask weights); false otherwise, for the general path
// (also for a folded or degenerate cell, a repeated cell, or cells too
// sparse for a dense index). `options` must be valid.
bool MeasureOnSameGrid(const Surface& a, const Surface& b, const MeasureOptions& options,
                       GridPairResult* out);

// The same for two rasters on lattices of the same cell vectors offset by a
// fraction of a cell (in either direction), with uniform weights: a sweep
// over A's cells, each triangle clipped by the triangles of the B cells
// around it (the general overlay's cells and cell integrator), and each
// node located in the other's cells with exact orientation tests.
bool MeasureOnOffsetGrids(const Surface& a, const Surface& b, const MeasureOptions& options,
                          GridPairResult* out);

// The same for B meshed on its own cells by the rule but with its samples
// anywhere (a raster moved by a rigid motion, turned, of another spacing)
// and A on a lattice, with uniform weights: each B triangle cut by A's
// column, row and diagonal lines into the overlay's cells (grid_moved.cc).
// False, for the general path, also when a node lies exactly on an edge of
// the other's mesh or B's triangles fold or turn the other way.
bool MeasureOnMovedGrid(const Surface& a, const Surface& b, const MeasureOptions& options,
                        GridPairResult* out);

// The summary's volume fields from an overlay's sums and the four areas
// (hulls of A and B, data domains of A and B), as Measure sets them.
void SetVolumeFields(const VolumeResult& volume, const std::array<double, 4>& areas,
                     const MeasureOptions& options, MeasureSummary* out);

}  // namespace surfreg

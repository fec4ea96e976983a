#pragma once
// Integration of the gap d = F̂_B − F̂_A over the overlap, for measures.cc:
// on the overlay cells (exact) or on the Delaunay triangulation of the nodes
// of A ∪ B inside Ω (the paper's union mode). Both in A's local frame.
#include <array>
#include <cstdint>
#include <vector>

#include "measure/delaunay.h"
#include "measure/domain.h"
#include "measure/locator.h"
#include "measure/tasks.h"
#include "measure/volume.h"
#include "measure/weights.h"

namespace surfreg {

// d at A's samples located in B (gaps.a) and at B's located in A (gaps.b);
// 0 for samples outside the other's hull.
struct NodeGaps {
  std::vector<double> a, b;
};

// Change beyond a level of detection L >= 0 (geomorphic change detection):
// only where |d| > L does the gap count as change.
struct DetectedChange {
  double fill = 0;       // ∫_{d > L} d μ
  double cut = 0;        // ∫_{d < −L} |d| μ
  double fill_area = 0;  // ∫_{d > L} μ
  double cut_area = 0;   // ∫_{d < −L} μ
  DetectedChange& operator+=(const DetectedChange& o) {
    fill += o.fill, cut += o.cut, fill_area += o.fill_area, cut_area += o.cut_area;
    return *this;
  }
};

// Ω as the intersection of the two data domains (measure/domain.h). A null
// domain is the whole hull of its surface; null node flags: every node found
// in the other surface's hull.
struct OmegaDomains {
  const MeshDomain* a = nullptr;
  const MeshDomain* b = nullptr;
  // Per sample (the index of xy_a / xy_b): 1 if the node lies in Ω.
  const std::vector<uint8_t>* nodes_a = nullptr;
  const std::vector<uint8_t>* nodes_b = nullptr;
};

struct VolumeResult {
  GapIntegrals gap;        // ∫|d|μ, ∫d⁺μ, ∫d⁻μ, ∫dμ, ∫μ
  DetectedChange change;   // with the `lod` given (all zero when lod < 0)
  double area = 0.0;       // unweighted area integrated over
  int64_t cells = 0;       // overlay cells or union triangles
};

// A convex polygon (n corners, counter-clockwise) clipped by a
// counter-clockwise triangle; writes the corners of the intersection to
// `out` (room for 9) and returns their number (< 3: empty).
int ClipByTriangle(const Point2* polygon, int n, const std::array<Point2, 3>& triangle,
                   Point2* out);

// Adds the integrals over a convex polygon (counter-clockwise, n corners) on
// which d is the linear function `d`, with μ as `mu` says (`mu_plane` for
// per-point weights); with lod >= 0 also the change beyond ±lod (each piece
// clipped by the lines d = ±lod: exact for linear d and μ); lod < 0: not.
void IntegrateConvex(const Point2* polygon, int n, const Plane& d, const WeightField& mu,
                     const Plane& mu_plane, VolumeResult* result, double lod = -1.0);

// On the threads `execution` allows, in chunks (overlay.h,
// ForEachOverlayCellInChunks): the same bits on any number of threads.
// Cells whose A or B triangle is outside its domain contribute nothing (and
// are not counted in `cells`).
VolumeResult OverlayVolume(const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                           const std::vector<double>& z_a, const std::vector<Location>& a_in_b,
                           const std::vector<Point2>& xy_b, const Triangulation& mesh_b,
                           const std::vector<double>& z_b, const std::vector<Location>& b_in_a,
                           const WeightField& mu, const Execution& execution = Execution{1}, double lod = -1.0,
                           const OmegaDomains& domains = OmegaDomains());

// The union's triangles use the paper's closed form for ∫|d| (volume.h,
// AbsVolumePaper) with μ = 1. The union is made of the nodes in Ω; its
// Delaunay triangles bridge the gaps between the domains again, so a
// triangle whose centroid is outside Ω (located in both meshes, exactly:
// LocateCentroid) is dropped.
VolumeResult UnionVolume(const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                         const std::vector<Location>& a_in_b, const std::vector<double>& gaps_a,
                         const std::vector<Point2>& xy_b, const Triangulation& mesh_b,
                         const std::vector<Location>& b_in_a, const std::vector<double>& gaps_b,
                         const WeightField& mu, const OmegaDomains& domains = OmegaDomains());

}  // namespace surfreg

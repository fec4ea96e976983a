#pragma once
// Asymmetry indices by region (docs/faces.md, "Indices by region"): the
// signed left-right difference of a face about its symmetry plane,
//   d = face − mirror   (> 0 where this side stands out more than the other),
// summarized over the whole overlap, the facial thirds, the two halves and
// regions the user draws, in the scan's units, each with a standard deviation.
//
// The difference is taken at every face sample (the mirror's linear
// interpolant there minus the sample's height) and integrated as the linear
// interpolant of those node values over the face's own Delaunay triangles;
// each triangle is clipped exactly to a region (a y band, a side of the
// plane, a polygon's triangles), and to d ≥ 0 / d ≤ 0 for ∫|d|, so an index
// is exact for that interpolant whatever the region's shape. The overlap is
// the face's data-domain triangles (measure/domain.h) whose corners all lie
// in the mirror's data domain.
//
// Regions, in the face frame (faces/face_frame.h: x across the face from the
// subject's right to left, y from chin to forehead):
//   upper_third, middle_third, lower_third: the overlap's y extent cut into
//     three equal bands (landmark-free: no soft-tissue points are located);
//   left, right: the subject's left (the plane's n·p > offset side, n_x > 0)
//     and right halves, the side taken on the surface (n·(x, y, F(x, y)));
//   the user's: simple polygons in the face frame's xy (input coordinates).
//
// Standard deviations add two independent parts: the surface noise (σ_n,
// estimated from the face's roughness: each sample against the plane of its
// Delaunay neighbours, robustly) propagated per sample (a sample's height
// enters its own d and, mirrored, the d of the nodes around its mirror
// image), and the plane's uncertainty (the least-absolute-deviations
// sandwich H⁻¹BH⁻¹ of the plane's two tilts and offset, J = ∂d/∂plane exact
// to first order) propagated through each index's gradient. Noise is taken
// as independent from sample to sample, so σ is a lower bound where the
// scan's errors are spatially correlated.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "faces/symmetry.h"
#include "measure/surface.h"

namespace surfreg {

struct FaceRegion {
  std::string name;                            // a JSON/CSV-safe name: [A-Za-z0-9_]+
  std::vector<std::array<double, 2>> polygon;  // simple, either orientation, face-frame xy
};

struct RegionIndex {
  std::string name;
  double area = 0;      // of the region within the overlap (units²)
  double rms = 0;       // sqrt(∫d² / area), units
  double mean_abs = 0;  // ∫|d| / area, units
  double mean = 0;      // ∫d / area, units (signed: > 0 this region stands out)
  double volume = 0;    // ∫d, units³
  double max_abs = 0;   // largest |d| in the region, units
  double rms_sigma = 0, mean_abs_sigma = 0, mean_sigma = 0, volume_sigma = 0;
  int64_t nodes = 0;  // face samples in the region with a difference
};

struct AsymmetryIndexOptions {
  bool standard_regions = true;     // the thirds and the halves
  std::vector<FaceRegion> regions;  // the user's, after the standard ones
  // σ_n of the face's heights (units); < 0: estimated from the face.
  double noise_sigma = -1;
};

struct AsymmetryIndices {
  RegionIndex whole;                 // the whole overlap ("face")
  std::vector<RegionIndex> regions;  // standard (if asked) then the user's, in order
  std::array<double, 4> thirds_y{};  // band edges, bottom to top (input coordinates)
  double noise_sigma = 0;            // σ_n used (units)
  // The plane's standard deviations: its normal's tilt towards y (about z)
  // and towards z (about y), in degrees, pivoting about the input origin (the
  // face frame's centre), and its offset (units).
  std::array<double, 3> plane_sigma{};
  // d = face − mirror at every face sample (input order; NaN outside the
  // mirror's data domain).
  std::vector<double> node_difference;

  const RegionIndex* Find(const std::string& name) const;  // whole, then regions; null if none
};

// Throws InputError for an invalid face, a region with an invalid name or
// polygon (fewer than 3 vertices, not simple, a name used twice or
// reserved), or a face that does not overlap its mirror.
AsymmetryIndices ComputeAsymmetryIndices(const Surface& face, const SymmetryPlane& plane,
                                         const AsymmetryIndexOptions& options = {});

// The names of the standard regions, in order.
const std::vector<std::string>& StandardRegionNames();

}  // namespace surfreg

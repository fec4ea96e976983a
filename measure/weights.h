#pragma once
// The weight μ(x, y) of the measures (measures.h, WeightMode), and how it is
// integrated exactly:
// - uniform: μ = 1;
// - per point: μ linear on each triangle of the mesh whose samples carry the
//   weights, so on an overlay cell both the gap d and μ are linear and
//   ∫|d|μ has a closed form (volume.h);
// - mask: μ = 1 on a region of rings (even–odd, measure/mask_region.h), 0
//   elsewhere. Each cell is clipped against the region's signed triangles
//   near it, so the integral is exact up to rounding of the clipped corners.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/delaunay.h"
#include "measure/locator.h"
#include "measure/mask_region.h"
#include "measure/measures.h"
#include "measure/surface.h"

namespace surfreg {

// z0 + gx (x - x0) + gy (y - y0): a linear function on the plane.
struct Plane {
  double x0 = 0, y0 = 0, z0 = 0, gx = 0, gy = 0;
  double At(const Point2& p) const { return z0 + gx * (p.x - x0) + gy * (p.y - y0); }
};
// The plane through (p_k, z_k), k = 0..2 (p not collinear).
Plane PlaneThrough(const Point2& p0, const Point2& p1, const Point2& p2, double z0, double z1,
                   double z2);

// μ for one comparison. Keeps references to the vectors it was made from,
// which must outlive it (they are Measure's locals).
class WeightField {
 public:
  WeightMode mode = WeightMode::kUniform;
  double AtNodeA(std::size_t i) const;  // μ at A's sample i (in Ω)
  double AtNodeB(std::size_t j) const;  // μ at B's sample j (in Ω)
  // Per point: μ on overlay cell (triangle_a, triangle_b) as a plane.
  Plane CellPlane(int32_t triangle_a, int32_t triangle_b) const;
  const MaskRegion& mask() const { return mask_; }

 private:
  friend WeightField MakeWeightField(const MeasureOptions&, const Surface&,
                                     const std::vector<Point2>&, const Triangulation&,
                                     const std::vector<double>&, const std::vector<Point2>&,
                                     const Triangulation&, const std::vector<double>&,
                                     const std::vector<Location>&, const std::vector<Location>&);
  // The surface whose samples carry the weights: A (first) or B.
  bool weights_on_a_ = true;
  const std::vector<Point2>* xy_ = nullptr;        // that surface's points
  const Triangulation* mesh_ = nullptr;            // and mesh
  const std::vector<double>* weight_ = nullptr;    // and weights
  const std::vector<Location>* other_in_this_ = nullptr;  // the other's nodes located in it
  MaskRegion mask_;                                // in A's local frame
  const std::vector<Point2>* xy_a_ = nullptr;
  const std::vector<Point2>* xy_b_ = nullptr;
};

// Builds μ for `options`; `a` gives the frame (A's origin) for the mask.
WeightField MakeWeightField(const MeasureOptions& options, const Surface& a,
                            const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                            const std::vector<double>& weight_a, const std::vector<Point2>& xy_b,
                            const Triangulation& mesh_b, const std::vector<double>& weight_b,
                            const std::vector<Location>& a_in_b,
                            const std::vector<Location>& b_in_a);

}  // namespace surfreg

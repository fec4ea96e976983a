#include "measure/weights.h"

#include <algorithm>
#include <cmath>

#include "measure/input_error.h"
#include "measure/predicates.h"

namespace surfreg {

Plane PlaneThrough(const Point2& p0, const Point2& p1, const Point2& p2, double z0, double z1,
                   double z2) {
  const double e1x = p1.x - p0.x, e1y = p1.y - p0.y, e2x = p2.x - p0.x, e2y = p2.y - p0.y;
  const double dz1 = z1 - z0, dz2 = z2 - z0;
  const double det = e1x * e2y - e1y * e2x;
  Plane plane{p0.x, p0.y, z0, 0.0, 0.0};
  if (det != 0.0) {
    plane.gx = (dz1 * e2y - dz2 * e1y) / det;
    plane.gy = (e1x * dz2 - e2x * dz1) / det;
  }
  return plane;
}

double WeightField::AtNodeA(std::size_t i) const {
  switch (mode) {
    case WeightMode::kUniform: return 1.0;
    case WeightMode::kMask: return InsideMask(mask_, (*xy_a_)[i]) ? 1.0 : 0.0;
    case WeightMode::kPerPoint:
      return weights_on_a_ ? (*weight_)[i] : InterpolateAt(*mesh_, *weight_, (*other_in_this_)[i]);
  }
  return 1.0;
}

double WeightField::AtNodeB(std::size_t j) const {
  switch (mode) {
    case WeightMode::kUniform: return 1.0;
    case WeightMode::kMask: return InsideMask(mask_, (*xy_b_)[j]) ? 1.0 : 0.0;
    case WeightMode::kPerPoint:
      return weights_on_a_ ? InterpolateAt(*mesh_, *weight_, (*other_in_this_)[j]) : (*weight_)[j];
  }
  return 1.0;
}

Plane WeightField::CellPlane(int32_t triangle_a, int32_t triangle_b) const {
  const int32_t t = weights_on_a_ ? triangle_a : triangle_b;
  const int32_t* v = &mesh_->triangles[3 * t];
  const std::vector<Point2>& xy = *xy_;
  const std::vector<double>& w = *weight_;
  return PlaneThrough(xy[v[0]], xy[v[1]], xy[v[2]], w[v[0]], w[v[1]], w[v[2]]);
}

WeightField MakeWeightField(const MeasureOptions& options, const Surface& a,
                            const std::vector<Point2>& xy_a, const Triangulation& mesh_a,
                            const std::vector<double>& weight_a, const std::vector<Point2>& xy_b,
                            const Triangulation& mesh_b, const std::vector<double>& weight_b,
                            const std::vector<Location>& a_in_b,
                            const std::vector<Location>& b_in_a) {
  WeightField field;
  field.mode = options.weight;
  field.xy_a_ = &xy_a;
  field.xy_b_ = &xy_b;
  if (options.weight == WeightMode::kPerPoint) {
    field.weights_on_a_ = !weight_a.empty();
    field.xy_ = field.weights_on_a_ ? &xy_a : &xy_b;
    field.mesh_ = field.weights_on_a_ ? &mesh_a : &mesh_b;
    field.weight_ = field.weights_on_a_ ? &weight_a : &weight_b;
    field.other_in_this_ = field.weights_on_a_ ? &b_in_a : &a_in_b;
  } else if (options.weight == WeightMode::kMask) {
    // Ω lies within A: exclude's enclosing ring need only cover A.
    field.mask_ = MakeMaskRegion(options.mask, options.mask_mode, {a.origin[0], a.origin[1]}, xy_a);
  }
  return field;
}

}  // namespace surfreg

#include "measure/weights.h"

#include <algorithm>
#include <cmath>

#include "measure/input_error.h"
#include "measure/predicates.h"

namespace surfreg {
namespace {

double TwiceSignedArea(const std::vector<Point2>& polygon) {
  double twice = 0.0;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    twice += (polygon[k].x - polygon[0].x) * (polygon[k + 1].y - polygon[0].y) -
             (polygon[k].y - polygon[0].y) * (polygon[k + 1].x - polygon[0].x);
  }
  return twice;
}

// Closed segments pq and rs share a point (exact).
bool SegmentsMeet(const Point2& p, const Point2& q, const Point2& r, const Point2& s) {
  const double o1 = Orient2D(p, q, r), o2 = Orient2D(p, q, s);
  const double o3 = Orient2D(r, s, p), o4 = Orient2D(r, s, q);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    return true;
  }
  auto on = [](const Point2& a, const Point2& b, const Point2& c, double o) {
    return o == 0.0 && std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) &&
           std::min(a.y, b.y) <= c.y && c.y <= std::max(a.y, b.y);
  };
  return on(p, q, r, o1) || on(p, q, s, o2) || on(r, s, p, o3) || on(r, s, q, o4);
}

// p inside or on triangle abc (counter-clockwise), exact.
bool InTriangle(const Point2& a, const Point2& b, const Point2& c, const Point2& p) {
  return Orient2D(a, b, p) >= 0.0 && Orient2D(b, c, p) >= 0.0 && Orient2D(c, a, p) >= 0.0;
}


}  // namespace

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

bool ValidMaskPolygon(const std::vector<std::array<double, 2>>& polygon, std::string* error) {
  const std::size_t n = polygon.size();
  if (n < 3) {
    *error = "mask polygon has " + std::to_string(n) + " vertices; at least 3 are needed";
    return false;
  }
  std::vector<Point2> p(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(polygon[k][0]) || !std::isfinite(polygon[k][1])) {
      *error = "mask polygon vertex " + std::to_string(k + 1) + " is not finite";
      return false;
    }
    p[k] = {polygon[k][0], polygon[k][1]};
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      const Point2 &a = p[i], &b = p[(i + 1) % n], &c = p[j], &d = p[(j + 1) % n];
      if (adjacent) {
        // Consecutive edges may only share their common vertex.
        const Point2& far = j == i + 1 ? d : c;
        const Point2& near_a = j == i + 1 ? a : b;
        const Point2& shared = j == i + 1 ? b : a;
        if (Orient2D(near_a, shared, far) == 0.0 &&
            ((far.x - shared.x) * (near_a.x - shared.x) + (far.y - shared.y) * (near_a.y - shared.y)) >
                0.0) {
          *error = "mask polygon folds back on itself at vertex " +
                   std::to_string((j == i + 1 ? i + 1 : 0) % n + 1);
          return false;
        }
        continue;
      }
      if (SegmentsMeet(a, b, c, d)) {
        *error = "mask polygon edges " + std::to_string(i + 1) + " and " + std::to_string(j + 1) +
                 " cross: the polygon must be simple";
        return false;
      }
    }
  }
  if (TwiceSignedArea(p) == 0.0) {
    *error = "mask polygon has zero area";
    return false;
  }
  return true;
}

std::vector<std::array<Point2, 3>> TriangulatePolygon(std::vector<Point2> polygon) {
  if (TwiceSignedArea(polygon) < 0.0) std::reverse(polygon.begin(), polygon.end());
  std::vector<std::array<Point2, 3>> triangles;
  std::vector<Point2> v = std::move(polygon);
  std::size_t guard = 0;
  while (v.size() > 3 && guard < 4 * v.size() * v.size() + 16) {
    const std::size_t n = v.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n && !clipped; ++i, ++guard) {
      const Point2& prev = v[(i + n - 1) % n];
      const Point2& cur = v[i];
      const Point2& next = v[(i + 1) % n];
      const double turn = Orient2D(prev, cur, next);
      if (turn == 0.0) {  // straight vertex: drop it, no area
        v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
        break;
      }
      if (turn < 0.0) continue;  // reflex
      bool ear = true;
      for (std::size_t k = 0; k < n && ear; ++k) {
        if (k == i || k == (i + 1) % n || k == (i + n - 1) % n) continue;
        if (InTriangle(prev, cur, next, v[k])) ear = false;
      }
      if (!ear) continue;
      triangles.push_back({prev, cur, next});
      v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) throw InputError("mask polygon could not be triangulated (is it simple?)");
  }
  if (v.size() == 3 && Orient2D(v[0], v[1], v[2]) > 0.0) triangles.push_back({v[0], v[1], v[2]});
  return triangles;
}

bool InsidePolygon(const std::vector<Point2>& polygon, const Point2& p) {
  const std::size_t n = polygon.size();
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Point2& a = polygon[j];
    const Point2& b = polygon[i];
    const double o = Orient2D(a, b, p);
    if (o == 0.0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
        std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y)) {
      return true;  // on the boundary
    }
    // Half-open crossing rule on edges that straddle the horizontal line.
    if ((a.y > p.y) != (b.y > p.y)) {
      const bool upward = b.y > a.y;
      if ((upward && o > 0.0) || (!upward && o < 0.0)) inside = !inside;
    }
  }
  return inside;
}

double WeightField::AtNodeA(std::size_t i) const {
  switch (mode) {
    case WeightMode::kUniform: return 1.0;
    case WeightMode::kMask: return InsidePolygon(mask_, (*xy_a_)[i]) ? 1.0 : 0.0;
    case WeightMode::kPerPoint:
      return weights_on_a_ ? (*weight_)[i] : InterpolateAt(*mesh_, *weight_, (*other_in_this_)[i]);
  }
  return 1.0;
}

double WeightField::AtNodeB(std::size_t j) const {
  switch (mode) {
    case WeightMode::kUniform: return 1.0;
    case WeightMode::kMask: return InsidePolygon(mask_, (*xy_b_)[j]) ? 1.0 : 0.0;
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
    for (const auto& v : options.mask_polygon) {
      field.mask_.push_back({v[0] - a.origin[0], v[1] - a.origin[1]});
    }
    field.mask_triangles_ = TriangulatePolygon(field.mask_);
  }
  return field;
}

}  // namespace surfreg

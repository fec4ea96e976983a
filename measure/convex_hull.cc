#include "measure/convex_hull.h"

#include <algorithm>

#include "measure/predicates.h"

namespace surfreg {

std::vector<Point2> ConvexHull(std::vector<Point2> points) {
  std::sort(points.begin(), points.end(),
            [](const Point2& p, const Point2& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); });
  points.erase(std::unique(points.begin(), points.end(),
                           [](const Point2& p, const Point2& q) { return p.x == q.x && p.y == q.y; }),
               points.end());
  if (points.size() < 3) return points;
  std::vector<Point2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && Orient2D(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && Orient2D(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

double PolygonArea(const std::vector<Point2>& p) {
  double twice = 0.0;  // a fan from corner 0: no cancellation far from the origin
  for (std::size_t k = 1; k + 1 < p.size(); ++k) {
    twice += (p[k].x - p[0].x) * (p[k + 1].y - p[0].y) - (p[k].y - p[0].y) * (p[k + 1].x - p[0].x);
  }
  return 0.5 * twice;
}

}  // namespace surfreg

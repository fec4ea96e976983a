#pragma once
// The convex hull of a point set in the plane, by Andrew's monotone chain
// with exact orientation tests (predicates.h).
#include <vector>

#include "measure/surface.h"

namespace surfreg {

// Counter-clockwise, no collinear corners, duplicates dropped; fewer than 3
// distinct points come back as they are (sorted).
std::vector<Point2> ConvexHull(std::vector<Point2> points);

// The area of a simple polygon (positive counter-clockwise).
double PolygonArea(const std::vector<Point2>& polygon);

}  // namespace surfreg

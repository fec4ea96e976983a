#pragma once
// Exact geometric predicates on double coordinates. Each is a fast
// floating-point evaluation with a forward error bound (Shewchuk 1997,
// "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates"); when the bound cannot certify the sign, the determinant is
// evaluated exactly with floating-point expansions. The returned value has
// the exact sign of the determinant (its magnitude is approximate).
#include "measure/surface.h"

namespace surfreg {

// > 0 if a, b, c turn counter-clockwise, < 0 clockwise, 0 if collinear.
double Orient2D(const Point2& a, const Point2& b, const Point2& c);

// > 0 if d lies inside the circle through a, b, c (given counter-clockwise),
// < 0 outside, 0 on it. Sign flips if a, b, c are clockwise.
double InCircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

// In-circle with symbolic perturbation: never 0 for four distinct points
// with a, b, c not collinear. Ties (d exactly on the circle) are broken as
// if each point's lifted height x² + y² were raised by an infinitesimal that
// is larger for lexicographically larger (x, then y) points. The tie-break
// depends only on coordinates, so the Delaunay triangulation it defines is
// unique and independent of input order (e.g. the diagonal chosen in each
// cell of a grid). Returns +1 (inside) or -1 (outside).
int InCirclePerturbed(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

// Counters of how often the exact stage ran (for tests and benchmarks).
struct PredicateCounters {
  unsigned long long orient_exact = 0;
  unsigned long long incircle_exact = 0;
  unsigned long long incircle_ties = 0;
};
PredicateCounters& ThreadPredicateCounters();

}  // namespace surfreg

#pragma once
// Independent checks of a Triangulation against its definition, by brute
// force and exact arithmetic (tests/testing/exact_rational.h); nothing here
// calls measure/predicates or measure/delaunay.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "measure/delaunay.h"
#include "tests/testing/exact_rational.h"

namespace surfreg::testing {

inline std::string Str(const Point2& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p.x << ", " << p.y << ")";
  return s.str();
}

// For each input index, the lowest input index with the same (x, y).
inline std::vector<int32_t> LowestIndexOfSameXY(const std::vector<Point2>& points) {
  std::vector<int32_t> idx(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) idx[i] = static_cast<int32_t>(i);
  std::sort(idx.begin(), idx.end(), [&](int32_t i, int32_t j) {
    const Point2 &p = points[i], &q = points[j];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return i < j;
  });
  std::vector<int32_t> rep(points.size());
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const bool same = k > 0 && points[idx[k]].x == points[idx[k - 1]].x &&
                      points[idx[k]].y == points[idx[k - 1]].y;
    rep[idx[k]] = same ? rep[idx[k - 1]] : idx[k];
  }
  return rep;
}

// Convex hull of the distinct points among `points` (input indices, one per
// distinct position), counter-clockwise, keeping every point on the hull
// boundary (also those in the middle of a hull edge). Andrew's monotone
// chain with exact orientation; a point is popped only on a strict right
// turn. Requires the points not to be all collinear.
inline std::vector<int32_t> ConvexHullWithCollinear(const std::vector<Point2>& points) {
  const std::vector<int32_t> rep = LowestIndexOfSameXY(points);
  std::vector<int32_t> v;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (rep[i] == static_cast<int32_t>(i)) v.push_back(static_cast<int32_t>(i));
  }
  std::sort(v.begin(), v.end(),
            [&](int32_t i, int32_t j) { return LexLessPoint(points[i], points[j]); });
  if (v.size() < 3) return v;
  std::vector<int32_t> lower, upper;
  for (int32_t i : v) {
    while (lower.size() >= 2 &&
           FilteredOrientSign(points[lower[lower.size() - 2]], points[lower.back()], points[i]) < 0) {
      lower.pop_back();
    }
    lower.push_back(i);
  }
  for (auto it = v.rbegin(); it != v.rend(); ++it) {
    const int32_t i = *it;
    while (upper.size() >= 2 &&
           FilteredOrientSign(points[upper[upper.size() - 2]], points[upper.back()], points[i]) < 0) {
      upper.pop_back();
    }
    upper.push_back(i);
  }
  lower.pop_back();
  upper.pop_back();
  lower.insert(lower.end(), upper.begin(), upper.end());
  return lower;
}

// Number of distinct points on the hull boundary by the O(n³) definition: p
// is on the boundary iff some line through p and another point has all the
// points on one closed side.
inline int BruteForceHullCount(const std::vector<Point2>& points) {
  const std::vector<int32_t> rep = LowestIndexOfSameXY(points);
  int count = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (rep[i] != static_cast<int32_t>(i)) continue;
    bool on_boundary = false;
    for (std::size_t j = 0; j < points.size() && !on_boundary; ++j) {
      if (rep[j] == rep[i]) continue;
      bool all_left = true;
      for (std::size_t k = 0; k < points.size() && all_left; ++k) {
        all_left = ExactOrientSign(points[i], points[j], points[k]) >= 0;
      }
      on_boundary = all_left;
    }
    count += on_boundary ? 1 : 0;
  }
  return count;
}

// Twice the area of the polygon, exactly (shoelace as a fan of exact
// orientation determinants from its first vertex).
inline Dyadic TwiceArea(const std::vector<Point2>& points, const std::vector<int32_t>& polygon) {
  Dyadic sum;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    sum = sum + ExactOrientDet(points[polygon[0]], points[polygon[k]], points[polygon[k + 1]]);
  }
  return sum;
}

using CoordTriangle = std::array<std::pair<double, double>, 3>;

// The triangles as sorted coordinate triples: comparable across inputs that
// list the same points in different orders.
inline std::set<CoordTriangle> CoordinateTriangles(const std::vector<Point2>& points,
                                                   const Triangulation& tri) {
  std::set<CoordTriangle> out;
  for (int32_t t = 0; t < tri.num_triangles(); ++t) {
    CoordTriangle c;
    for (int i = 0; i < 3; ++i) {
      const Point2& p = points.at(tri.triangles[3 * t + i]);
      c[i] = {p.x, p.y};
    }
    std::sort(c.begin(), c.end());
    out.insert(c);
  }
  return out;
}

struct DelaunayCheckOptions {
  // Check the empty-circle property against every point (O(n·t)) below this
  // size; above it, against the points in grid cells that a conservatively
  // enlarged circumcircle's bounding box overlaps (skinny triangles, whose
  // circumcentre is ill-conditioned, are still checked against all points).
  std::size_t brute_force_limit = 1500;
};

// Checks that `tri` is the Delaunay triangulation of `points` with ties
// broken by the documented symbolic perturbation. Returns a failure listing
// the first problems found.
inline ::testing::AssertionResult IsPerturbedDelaunay(const std::vector<Point2>& points,
                                                      const Triangulation& tri,
                                                      DelaunayCheckOptions options = {}) {
  std::vector<std::string> errors;
  std::size_t total_errors = 0;
  auto fail = [&](const std::string& message) {
    ++total_errors;
    if (errors.size() < 12) errors.push_back(message);
  };
  auto result = [&]() {
    if (total_errors == 0) return ::testing::AssertionSuccess();
    ::testing::AssertionResult r = ::testing::AssertionFailure();
    r << total_errors << " problem(s):";
    for (const std::string& e : errors) r << "\n  " << e;
    return r;
  };

  const std::size_t n = points.size();
  const int32_t nt = tri.num_triangles();
  // --- Sizes.
  if (tri.triangles.size() % 3 != 0) fail("triangles.size() not a multiple of 3");
  if (tri.neighbors.size() != tri.triangles.size()) fail("neighbors.size() != triangles.size()");
  if (tri.vertex_triangle.size() != n) fail("vertex_triangle.size() != number of points");
  if (tri.vertex_of_input.size() != n) fail("vertex_of_input.size() != number of points");
  if (total_errors > 0) return result();

  // --- Duplicates.
  const std::vector<int32_t> rep = LowestIndexOfSameXY(points);
  std::size_t distinct = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rep[i] == static_cast<int32_t>(i)) ++distinct;
    if (tri.vertex_of_input[i] != rep[i]) {
      fail("vertex_of_input[" + std::to_string(i) + "] = " + std::to_string(tri.vertex_of_input[i]) +
           ", expected " + std::to_string(rep[i]) + " (lowest index at " + Str(points[i]) + ")");
    }
  }
  if (tri.num_duplicates != static_cast<int32_t>(n - distinct)) {
    fail("num_duplicates = " + std::to_string(tri.num_duplicates) + ", expected " +
         std::to_string(n - distinct));
  }

  // --- Vertex indices and orientation.
  for (int32_t t = 0; t < nt; ++t) {
    const int32_t* v = &tri.triangles[3 * t];
    bool ok = true;
    for (int i = 0; i < 3; ++i) {
      if (v[i] < 0 || static_cast<std::size_t>(v[i]) >= n) {
        fail("triangle " + std::to_string(t) + " has vertex index " + std::to_string(v[i]));
        ok = false;
      } else if (rep[v[i]] != v[i]) {
        fail("triangle " + std::to_string(t) + " uses merged duplicate " + std::to_string(v[i]));
      }
    }
    if (!ok) continue;
    const int s = FilteredOrientSign(points[v[0]], points[v[1]], points[v[2]]);
    if (s <= 0) {
      fail("triangle " + std::to_string(t) + " " + Str(points[v[0]]) + Str(points[v[1]]) +
           Str(points[v[2]]) + (s == 0 ? " is degenerate" : " is clockwise"));
    }
  }
  if (total_errors > 0) return result();

  // --- Directed edges unique; neighbours consistent.
  std::map<std::pair<int32_t, int32_t>, std::pair<int32_t, int>> edge;  // (from,to) -> (t, i)
  for (int32_t t = 0; t < nt; ++t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t a = tri.triangles[3 * t + (i + 1) % 3], b = tri.triangles[3 * t + (i + 2) % 3];
      if (!edge.emplace(std::make_pair(a, b), std::make_pair(t, i)).second) {
        fail("directed edge " + std::to_string(a) + "->" + std::to_string(b) +
             " in more than one triangle (edge shared by > 2 triangles or overlap)");
      }
    }
  }
  std::vector<std::pair<int32_t, int32_t>> boundary;
  for (int32_t t = 0; t < nt; ++t) {
    for (int i = 0; i < 3; ++i) {
      const int32_t a = tri.triangles[3 * t + (i + 1) % 3], b = tri.triangles[3 * t + (i + 2) % 3];
      const int32_t u = tri.neighbors[3 * t + i];
      const auto twin = edge.find({b, a});
      if (u == -1) {
        if (twin != edge.end()) {
          fail("triangle " + std::to_string(t) + " edge " + std::to_string(i) +
               " has neighbor -1 but triangle " + std::to_string(twin->second.first) +
               " has the reversed edge");
        }
        boundary.emplace_back(a, b);
        continue;
      }
      if (u < 0 || u >= nt) {
        fail("neighbors[" + std::to_string(3 * t + i) + "] = " + std::to_string(u) + " out of range");
        continue;
      }
      if (twin == edge.end() || twin->second.first != u) {
        fail("triangle " + std::to_string(t) + " edge " + std::to_string(i) + " (" +
             std::to_string(a) + "->" + std::to_string(b) + ") names neighbor " +
             std::to_string(u) + " which does not hold " + std::to_string(b) + "->" +
             std::to_string(a));
        continue;
      }
      if (tri.neighbors[3 * u + twin->second.second] != t) {
        fail("neighbor of triangle " + std::to_string(u) + " across " + std::to_string(b) + "->" +
             std::to_string(a) + " is " + std::to_string(tri.neighbors[3 * u + twin->second.second]) +
             ", expected " + std::to_string(t));
      }
    }
  }

  // --- Every distinct point is a vertex; vertex_triangle.
  std::vector<char> used(n, 0);
  for (int32_t v : tri.triangles) used[v] = 1;
  for (std::size_t i = 0; i < n; ++i) {
    const bool kept = rep[i] == static_cast<int32_t>(i);
    if (kept && !used[i]) fail("distinct point " + std::to_string(i) + " " + Str(points[i]) + " is not a vertex");
    const int32_t t = tri.vertex_triangle[i];
    if (!kept) {
      if (t != -1) fail("vertex_triangle[" + std::to_string(i) + "] of a merged duplicate is " + std::to_string(t));
    } else if (t < 0 || t >= nt ||
               (tri.triangles[3 * t] != static_cast<int32_t>(i) &&
                tri.triangles[3 * t + 1] != static_cast<int32_t>(i) &&
                tri.triangles[3 * t + 2] != static_cast<int32_t>(i))) {
      fail("vertex_triangle[" + std::to_string(i) + "] = " + std::to_string(t) +
           " does not contain the vertex");
    }
  }

  // --- Hull: Euler count, boundary edges = hull edges, area.
  const std::vector<int32_t> hull = ConvexHullWithCollinear(points);
  const auto h = static_cast<int64_t>(hull.size());
  const int64_t expected_triangles = 2 * static_cast<int64_t>(distinct) - 2 - h;
  if (nt != expected_triangles) {
    fail("num_triangles = " + std::to_string(nt) + ", expected 2n - 2 - h = " +
         std::to_string(expected_triangles) + " (n = " + std::to_string(distinct) +
         " distinct, h = " + std::to_string(h) + ")");
  }
  if (static_cast<int64_t>(boundary.size()) != h) {
    fail(std::to_string(boundary.size()) + " edges with neighbor -1, expected h = " + std::to_string(h));
  }
  std::set<std::pair<int32_t, int32_t>> hull_edges;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    hull_edges.emplace(hull[k], hull[(k + 1) % hull.size()]);
  }
  for (const auto& e : boundary) {
    if (!hull_edges.count(e)) {
      fail("boundary edge " + Str(points[e.first]) + "->" + Str(points[e.second]) +
           " is not a counter-clockwise edge between consecutive hull points");
    }
  }
  Dyadic area;
  for (int32_t t = 0; t < nt; ++t) {
    area = area + ExactOrientDet(points[tri.triangles[3 * t]], points[tri.triangles[3 * t + 1]],
                                 points[tri.triangles[3 * t + 2]]);
  }
  const Dyadic hull_area = TwiceArea(points, hull);
  if (area != hull_area) fail("sum of triangle areas differs (exactly) from the hull area");
  if (total_errors > 0) return result();

  // --- Empty circles, ties decided by the documented perturbation.
  std::vector<int32_t> kept;
  double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY, max_abs = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rep[i] != static_cast<int32_t>(i)) continue;
    kept.push_back(static_cast<int32_t>(i));
    min_x = std::min(min_x, points[i].x);
    max_x = std::max(max_x, points[i].x);
    min_y = std::min(min_y, points[i].y);
    max_y = std::max(max_y, points[i].y);
    max_abs = std::max({max_abs, std::fabs(points[i].x), std::fabs(points[i].y)});
  }
  const double extent = std::max(max_x - min_x, max_y - min_y);
  const int cells = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(kept.size()) / 2.0)));
  const double cell_w = (max_x - min_x) / cells, cell_h = (max_y - min_y) / cells;
  auto cell_of = [&](double v, double lo, double w) {
    if (!(w > 0.0)) return 0;
    return std::clamp(static_cast<int>(std::floor((v - lo) / w)), 0, cells - 1);
  };
  std::vector<std::vector<int32_t>> grid(static_cast<std::size_t>(cells) * cells);
  for (int32_t i : kept) {
    grid[static_cast<std::size_t>(cell_of(points[i].y, min_y, cell_h)) * cells +
         cell_of(points[i].x, min_x, cell_w)]
        .push_back(i);
  }

  std::vector<int32_t> candidates;
  for (int32_t t = 0; t < nt; ++t) {
    const int32_t* v = &tri.triangles[3 * t];
    const Point2 &a = points[v[0]], &b = points[v[1]], &c = points[v[2]];
    candidates.clear();
    bool all = kept.size() <= options.brute_force_limit;
    double cx = 0.0, cy = 0.0, radius = 0.0;
    if (!all) {
      // Circumcentre relative to a.
      const double bx = b.x - a.x, by = b.y - a.y, qx = c.x - a.x, qy = c.y - a.y;
      const double d = 2.0 * (bx * qy - by * qx);
      const double b2 = bx * bx + by * by, c2 = qx * qx + qy * qy;
      const double longest = std::max({b2, c2, (c.x - b.x) * (c.x - b.x) + (c.y - b.y) * (c.y - b.y)});
      const double quality = std::fabs(d) / longest;  // ~ sine of the smallest angle
      const double ux = (qy * b2 - by * c2) / d, uy = (bx * c2 - qx * b2) / d;
      radius = std::sqrt(ux * ux + uy * uy);
      cx = a.x + ux;
      cy = a.y + uy;
      if (!(quality > 1e-4) || !std::isfinite(radius) || !std::isfinite(cx) || !std::isfinite(cy)) {
        all = true;
      } else {
        radius += 1e-6 * radius + 1e-9 * extent + 8.0 * max_abs * 2.220446049250313e-16;
      }
    }
    if (all) {
      candidates = kept;
    } else {
      const int x0 = cell_of(cx - radius, min_x, cell_w), x1 = cell_of(cx + radius, min_x, cell_w);
      const int y0 = cell_of(cy - radius, min_y, cell_h), y1 = cell_of(cy + radius, min_y, cell_h);
      for (int gy = y0; gy <= y1; ++gy) {
        for (int gx = x0; gx <= x1; ++gx) {
          for (int32_t i : grid[static_cast<std::size_t>(gy) * cells + gx]) {
            const Point2& p = points[i];
            if (std::fabs(p.x - cx) <= radius && std::fabs(p.y - cy) <= radius) candidates.push_back(i);
          }
        }
      }
    }
    for (int32_t i : candidates) {
      if (i == v[0] || i == v[1] || i == v[2]) continue;
      const Point2& d = points[i];
      const int s = FilteredInCircleSign(a, b, c, d);
      if (s > 0) {
        fail("point " + std::to_string(i) + " " + Str(d) + " is strictly inside the circumcircle of triangle " +
             std::to_string(t) + " " + Str(a) + Str(b) + Str(c));
      } else if (s == 0 && ExactInCirclePerturbedSign(a, b, c, d) >= 0) {
        fail("cocircular point " + std::to_string(i) + " " + Str(d) + " of triangle " + std::to_string(t) +
             " " + Str(a) + Str(b) + Str(c) + " is inside under the documented tie rule");
      }
    }
  }
  return result();
}

}  // namespace surfreg::testing

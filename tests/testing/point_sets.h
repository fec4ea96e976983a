#pragma once
// Seeded synthetic xy point sets for tests and benchmarks: the inputs real
// scans are made of (irregular clouds, grids, tilted grids, clusters) and the
// degenerate ones that break naive code (collinear runs, cocircular sets).
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "measure/surface.h"

namespace surfreg::testing {

// n points uniform in [0, 1)^2.
inline std::vector<Point2> UniformPoints(std::size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point2> points(n);
  for (Point2& p : points) p = {u(rng), u(rng)};
  return points;
}

// A cols x rows grid with spacing `step`, origin (x0, y0), row by row.
// Every cell is cocircular: the hard case for Delaunay.
inline std::vector<Point2> GridPoints(int cols, int rows, double step = 1.0, double x0 = 0.0,
                                      double y0 = 0.0) {
  std::vector<Point2> points;
  points.reserve(static_cast<std::size_t>(cols) * rows);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) points.push_back({x0 + c * step, y0 + r * step});
  }
  return points;
}

// The grid of GridPoints, each point moved by up to `jitter` * step in x and y.
inline std::vector<Point2> JitteredGridPoints(int cols, int rows, double jitter, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  std::vector<Point2> points = GridPoints(cols, rows);
  for (Point2& p : points) p = {p.x + u(rng), p.y + u(rng)};
  return points;
}

// The grid rotated by `degrees` about the origin (coordinates rounded, so
// cells are cocircular only approximately: the filter cannot decide them).
inline std::vector<Point2> RotatedGridPoints(int cols, int rows, double degrees) {
  const double a = degrees * M_PI / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  std::vector<Point2> points = GridPoints(cols, rows);
  for (Point2& p : points) p = {c * p.x - s * p.y, s * p.x + c * p.y};
  return points;
}

// `clusters` tight Gaussian clusters (sigma `spread`) of n / clusters points.
inline std::vector<Point2> ClusteredPoints(std::size_t n, int clusters, double spread,
                                           uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, spread);
  std::vector<Point2> centres(clusters);
  for (Point2& c : centres) c = {u(rng), u(rng)};
  std::vector<Point2> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& c = centres[i % clusters];
    points[i] = {c.x + g(rng), c.y + g(rng)};
  }
  return points;
}

// n points evenly on the unit circle, snapped to a 2^-20 lattice so that the
// exact predicates see exact values (several subsets are exactly cocircular
// when n is a multiple of 4: (±1, 0), (0, ±1)).
inline std::vector<Point2> CirclePoints(int n) {
  std::vector<Point2> points(n);
  const double q = 1048576.0;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    points[i] = {std::round(std::cos(a) * q) / q, std::round(std::sin(a) * q) / q};
  }
  return points;
}

// n points on the x axis (0..n-1) plus one point above the middle.
inline std::vector<Point2> CollinearPlusOne(int n) {
  std::vector<Point2> points;
  for (int i = 0; i < n; ++i) points.push_back({static_cast<double>(i), 0.0});
  points.push_back({(n - 1) / 2.0, 1.0});
  return points;
}

}  // namespace surfreg::testing

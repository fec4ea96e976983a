#pragma once
// Registration test fixtures shared by registration_costs_test.cc and
// pair_state_test.cc: a reference/moving pair prepared for a PairState,
// weights as functions, motions and heights computed independently of
// surfreg's own code (Eigen's AngleAxis, a brute-force triangle search).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "measure/delaunay.h"
#include "measure/surface.h"
#include "registration/pair_state.h"
#include "tests/testing/surface_pairs.h"

namespace surfreg {

using Theta = std::array<double, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// Both sides of a pair; heap-held because PairState keeps references.
struct Sides {
  Surface a, b;
  ReferenceSide reference;
  MovingSide moving;
  double radius = 1;  // B's RMS radius: rotations × radius are lengths
};

// μ(x, y) given as a function, sampled at the reference's points.
using WeightFunction = std::function<double(double, double)>;

// A smooth weight in [0.2, 0.8] (no zeros: sqrt(μ) is smooth), and a 0/1
// one (0 on a disc: what a raster mask gives).
inline double SmoothWeight(double x, double y) { return 0.5 + 0.3 * std::sin(x / 13.0) * std::cos(y / 17.0); }
inline double DiscZero(double x, double y) { return std::hypot(x - 60, y - 45) < 20 ? 0.0 : 1.0; }

// The exact tests compare with independent computations over the whole
// convex hulls (`rule` kHull); the data domain has tests of its own.
inline DomainRule HullRule() {
  DomainRule rule;
  rule.kind = DomainKind::kHull;
  return rule;
}

inline std::unique_ptr<Sides> MakeSides(const std::vector<std::array<double, 3>>& pa,
                                 const std::vector<std::array<double, 3>>& pb,
                                 const WeightFunction& weight = nullptr,
                                 const DomainRule& rule = HullRule()) {
  auto s = std::make_unique<Sides>();
  std::vector<double> mu;
  for (const auto& p : pa) {
    if (weight) mu.push_back(weight(p[0], p[1]));
  }
  s->a = MakeSurface(pa, mu, "a");
  s->b = MakeSurface(pb, {}, "b");
  s->reference = PrepareReference(s->a, 1.0, rule);
  s->moving = PrepareMoving(s->b, {s->b.origin[0] - s->a.origin[0], s->b.origin[1] - s->a.origin[1],
                                   s->b.origin[2] - s->a.origin[2]}, 1.0, rule);
  double sum = 0;
  for (const auto& p : s->moving.points) sum += (p - s->moving.centroid).squaredNorm();
  s->radius = std::sqrt(sum / s->moving.points.size());
  return s;
}

// Two different random samplings of SmoothTerrain; B on [b0, b1]².
inline std::unique_ptr<Sides> TerrainSides(int na, int nb, double b0, double b1,
                                    const WeightFunction& weight = nullptr,
                                    const DomainRule& rule = HullRule()) {
  return MakeSides(testing::SampleUniform(testing::SmoothTerrain, na, 0, 100, 0, 100, 11),
                   testing::SampleUniform(testing::SmoothTerrain, nb, b0, b1, b0, b1, 23), weight, rule);
}

// Two samplings of SmoothTerrain on [0, 100]², each with a void (a disc of
// radius 12 with no samples: A's about (35, 60), B's about (65, 40)), with
// the data domain: the voids' bridging triangles are junk.
inline std::vector<std::array<double, 3>> WithoutDisc(std::vector<std::array<double, 3>> points,
                                                      double cx, double cy, double r) {
  points.erase(std::remove_if(points.begin(), points.end(),
                              [&](const std::array<double, 3>& p) { return std::hypot(p[0] - cx, p[1] - cy) < r; }),
               points.end());
  return points;
}

inline std::unique_ptr<Sides> VoidSides(int na, int nb) {
  return MakeSides(WithoutDisc(testing::SampleUniform(testing::SmoothTerrain, na, 0, 100, 0, 100, 11), 35, 60, 12),
                   WithoutDisc(testing::SampleUniform(testing::SmoothTerrain, nb, 0, 100, 0, 100, 23), 65, 40, 12),
                   nullptr, DomainRule());
}

// The moved point computed with Eigen's AngleAxis (not surfreg's rotation code).
inline Eigen::Vector3d Moved(const MovingSide& m, const Theta& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d w(t[0], t[1], t[2]);
  const Eigen::Matrix3d r =
      w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).matrix() : Eigen::Matrix3d::Identity();
  return r * (p - m.centroid) + m.centroid + Eigen::Vector3d(t[3], t[4], t[5]);
}

// Height at (x, y) of the triangle of `corners` that contains it (own
// brute-force search, plain double barycentrics); false if none does.
inline bool HeightAt(const std::vector<Eigen::Vector3d>& corners, const Triangulation& mesh, double x,
              double y, double* z) {
  for (int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d& p0 = corners[mesh.triangles[3 * t]];
    const Eigen::Vector3d& p1 = corners[mesh.triangles[3 * t + 1]];
    const Eigen::Vector3d& p2 = corners[mesh.triangles[3 * t + 2]];
    const double det = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p1.y() - p0.y()) * (p2.x() - p0.x());
    const double l1 = ((x - p0.x()) * (p2.y() - p0.y()) - (y - p0.y()) * (p2.x() - p0.x())) / det;
    const double l2 = ((p1.x() - p0.x()) * (y - p0.y()) - (p1.y() - p0.y()) * (x - p0.x())) / det;
    if (l1 < -1e-12 || l2 < -1e-12 || l1 + l2 > 1 + 1e-12) continue;
    *z = (1 - l1 - l2) * p0.z() + l1 * p1.z() + l2 * p2.z();
    return true;
  }
  return false;
}

}  // namespace surfreg

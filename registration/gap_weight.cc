#include "registration/gap_weight.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace surfreg {

namespace {

// The most neighbours a ring may have before it is not looked at (a vertex
// of a degenerate fan).
constexpr int kMaxRing = 64;

// The offsets of v's Delaunay neighbours from v, around its ring of
// triangles; their count, or −1 unless the ring closes.
int RingOffsets(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh, std::size_t v,
                std::array<Eigen::Vector3d, kMaxRing>* offsets) {
  const int32_t first = mesh.vertex_triangle[v];
  if (first < 0) return -1;
  int32_t t = first;
  int count = 0;
  do {  // around v: across the edge from v to its successor's successor
    int i = 0;
    while (mesh.triangles[3 * t + i] != static_cast<int32_t>(v)) ++i;
    (*offsets)[count++] = points[mesh.triangles[3 * t + (i + 1) % 3]] - points[v];
    t = mesh.neighbors[3 * t + (i + 1) % 3];
  } while (t >= 0 && t != first && count < kMaxRing);
  return t == first ? count : -1;
}

}  // namespace

std::vector<double> PlaneGaps(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh,
                              std::size_t stride) {
  std::vector<double> gap(points.size(), -1.0);
  std::array<Eigen::Vector3d, kMaxRing> ring;
  for (std::size_t v = 0; v < points.size(); v += std::max<std::size_t>(stride, 1)) {
    const int neighbours = RingOffsets(points, mesh, v, &ring);
    if (neighbours < 3) continue;
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();  // of z = c0 + c1 dx + c2 dy
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (int k = 0; k < neighbours; ++k) {
      const Eigen::Vector3d row(1.0, ring[k].x(), ring[k].y());
      normal += row * row.transpose();
      rhs += row * ring[k].z();
    }
    const Eigen::Vector3d plane = normal.ldlt().solve(rhs);
    if (std::isfinite(plane[0])) gap[v] = std::fabs(plane[0]);
  }
  return gap;
}

std::vector<double> CurvatureGaps(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh) {
  using Vector5 = Eigen::Matrix<double, 5, 1>;
  using Matrix5 = Eigen::Matrix<double, 5, 5>;
  std::vector<double> gap(points.size(), -1.0);  // first |λ₁| + |λ₂| of H
  std::vector<double> spacing2;                   // the rings' ℓ²
  std::array<Eigen::Vector3d, kMaxRing> ring;
  for (std::size_t v = 0; v < points.size(); ++v) {
    const int neighbours = RingOffsets(points, mesh, v, &ring);
    if (neighbours < 5) continue;
    double l2 = 0;
    for (int k = 0; k < neighbours; ++k) l2 += ring[k].head<2>().squaredNorm();
    l2 /= neighbours;
    if (!(l2 > 0)) continue;
    // z = a·u + ½ uᵀH'u through v, u = d / ℓ: unit-free, so the normal
    // equations are as well conditioned in metres as in millimetres (H' = ℓ² H).
    const double inv_l = 1.0 / std::sqrt(l2);
    Matrix5 normal = Matrix5::Zero();
    Vector5 rhs = Vector5::Zero();
    for (int k = 0; k < neighbours; ++k) {
      const double ux = ring[k].x() * inv_l, uy = ring[k].y() * inv_l;
      const Vector5 row(ux, uy, 0.5 * ux * ux, ux * uy, 0.5 * uy * uy);
      normal.selfadjointView<Eigen::Lower>().rankUpdate(row);
      rhs += row * ring[k].z();
    }
    // Cholesky (it reads the lower triangle only); a ring that does not
    // determine a quadratic (its points on a conic through v) shows as a
    // vanishing pivot.
    const Eigen::LLT<Matrix5> solver(normal);
    if (solver.info() != Eigen::Success) continue;
    const Vector5 pivots = solver.matrixLLT().diagonal();
    if (!(pivots.minCoeff() > 1e-4 * pivots.maxCoeff())) continue;
    const Vector5 c = solver.solve(rhs);  // a, then H' as c2, c3, c4
    // |λ₁| + |λ₂| of [[c2, c3], [c3, c4]] in closed form.
    const double mean = 0.5 * (c[2] + c[4]), radius = std::hypot(0.5 * (c[2] - c[4]), c[3]);
    const double curvature = (std::fabs(mean + radius) + std::fabs(mean - radius)) / l2;
    if (!std::isfinite(curvature)) continue;
    gap[v] = curvature;
    spacing2.push_back(l2);
  }
  if (spacing2.empty()) return gap;
  std::nth_element(spacing2.begin(), spacing2.begin() + spacing2.size() / 2, spacing2.end());
  const double l2 = spacing2[spacing2.size() / 2];
  for (double& g : gap)
    if (g >= 0) g *= 0.25 * l2;
  return gap;
}

void ApplyGapWeight(double floor_fraction, ReferenceSide* reference) {
  if (floor_fraction == 0) return;
  ReferenceSide& a = *reference;
  std::vector<Eigen::Vector3d> points(a.xy.size());
  for (std::size_t v = 0; v < a.xy.size(); ++v) points[v] = {a.xy[v].x, a.xy[v].y, a.z[v]};
  const std::vector<double> own = CurvatureGaps(points, a.mesh);
  // The node's local gap: the mean, over the triangles around it, of their
  // corners' own gaps. An average, not the largest: on a noisy surface the
  // largest of a ring picks the noise's extremes, and weights correlated
  // with the noise draw cost accuracy there (measured: docs/registration.md).
  std::vector<double> sum(points.size(), 0.0);
  std::vector<int32_t> count(points.size(), 0);
  for (int32_t t = 0; t < a.mesh.num_triangles(); ++t) {
    const int32_t* v = &a.mesh.triangles[3 * t];
    for (int j = 0; j < 3; ++j) {
      if (own[v[j]] < 0) continue;
      for (int i = 0; i < 3; ++i) {
        sum[v[i]] += own[v[j]];
        ++count[v[i]];
      }
    }
  }
  std::vector<double> local(points.size(), -1.0);
  for (std::size_t v = 0; v < points.size(); ++v)
    if (count[v] > 0) local[v] = sum[v] / count[v];
  std::vector<double> known;
  for (double g : local)
    if (g >= 0) known.push_back(g);
  if (known.empty()) return;  // no node with a closed ring: nothing to go by
  std::nth_element(known.begin(), known.begin() + known.size() / 2, known.end());
  const double median = known[known.size() / 2];
  // Gaps at rounding level (a plane, a flat region) carry no scale: the
  // floor is at least 1e-9 of the data's extent.
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : points) box.extend(p);
  const double floor = std::max(floor_fraction * median, 1e-9 * box.diagonal().norm());
  if (a.weight.empty()) a.weight.assign(points.size(), 1.0);
  for (std::size_t v = 0; v < points.size(); ++v)
    a.weight[v] *= floor / (floor + (local[v] >= 0 ? local[v] : median));
}

}  // namespace surfreg

#include "registration/ring_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace surfreg {

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

bool FitRingQuadratic(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh, std::size_t v,
                      double noise, RingQuadratic* out) {
  using Vector5 = Eigen::Matrix<double, 5, 1>;
  using Matrix5 = Eigen::Matrix<double, 5, 5>;
  std::array<Eigen::Vector3d, kMaxRing> ring;
  const int neighbours = RingOffsets(points, mesh, v, &ring);
  if (neighbours < 5) return false;
  double l2 = 0;
  for (int k = 0; k < neighbours; ++k) l2 += ring[k].head<2>().squaredNorm();
  l2 /= neighbours;
  if (!(l2 > 0)) return false;
  // z = a·u + ½ uᵀH'u through v, u = d / ℓ: unit-free, so the normal
  // equations are as well conditioned in metres as in millimetres (H' = ℓ² H).
  const double inv_l = 1.0 / std::sqrt(l2);
  Matrix5 normal = Matrix5::Zero();
  Vector5 rhs = Vector5::Zero();
  Vector5 row_sum = Vector5::Zero();
  for (int k = 0; k < neighbours; ++k) {
    const double ux = ring[k].x() * inv_l, uy = ring[k].y() * inv_l;
    const Vector5 row(ux, uy, 0.5 * ux * ux, ux * uy, 0.5 * uy * uy);
    normal.selfadjointView<Eigen::Lower>().rankUpdate(row);
    rhs += row * ring[k].z();
    row_sum += row;
  }
  // Cholesky (it reads the lower triangle only); a ring that does not
  // determine a quadratic shows as a vanishing pivot.
  const Eigen::LLT<Matrix5> solver(normal);
  if (solver.info() != Eigen::Success) return false;
  const Vector5 pivots = solver.matrixLLT().diagonal();
  if (!(pivots.minCoeff() > 1e-4 * pivots.maxCoeff())) return false;
  const Vector5 c = solver.solve(rhs);  // a, then H' as c2, c3, c4
  double shrink = 1.0;
  if (noise > 0) {
    // The offsets z_k − z_v all carry v's noise: Cov(z offsets) = σ²(I + 11ᵀ),
    // so Cov(c) = σ²(N⁻¹ + N⁻¹s sᵀN⁻¹), s the sum of the rows.
    const Matrix5 inverse = solver.solve(Matrix5::Identity());
    const Vector5 is = inverse * row_sum;
    const Matrix5 cov = noise * noise * (inverse + is * is.transpose());
    const double expected = cov(2, 2) + 2 * cov(3, 3) + cov(4, 4);
    const double observed = c[2] * c[2] + 2 * c[3] * c[3] + c[4] * c[4];
    shrink = observed > 0 ? std::max(0.0, 1.0 - expected / observed) : 0.0;
  }
  out->hessian = Eigen::Vector3d(c[2], c[3], c[4]) * (shrink / l2);
  out->spacing2 = l2;
  return out->hessian.allFinite();
}

double SampleNoise(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh) {
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  std::vector<double> scaled;  // per vertex RSS / dof / (median of χ²_dof / dof)
  std::array<Eigen::Vector3d, kMaxRing> ring;
  std::array<Vector6, kMaxRing + 1> rows;
  std::array<double, kMaxRing + 1> z;
  for (std::size_t v = 0; v < points.size(); ++v) {
    const int neighbours = RingOffsets(points, mesh, v, &ring);
    if (neighbours < 6) continue;  // a quadratic with a constant would leave no residual
    double l2 = 0;
    for (int k = 0; k < neighbours; ++k) l2 += ring[k].head<2>().squaredNorm();
    l2 /= neighbours;
    if (!(l2 > 0)) continue;
    const double inv_l = 1.0 / std::sqrt(l2);
    // v is the row (1, 0, …, 0): with the constant free, v's sample is
    // fitted like its neighbours', not interpolated.
    const int n = neighbours + 1;
    Matrix6 normal = Matrix6::Zero();
    Vector6 rhs = Vector6::Zero();
    for (int k = 0; k < n; ++k) {
      const bool own = k == neighbours;
      const double ux = own ? 0.0 : ring[k].x() * inv_l, uy = own ? 0.0 : ring[k].y() * inv_l;
      z[k] = own ? 0.0 : ring[k].z();
      rows[k] << 1.0, ux, uy, 0.5 * ux * ux, ux * uy, 0.5 * uy * uy;
      normal.selfadjointView<Eigen::Lower>().rankUpdate(rows[k]);
      rhs += rows[k] * z[k];
    }
    const Eigen::LLT<Matrix6> solver(normal);
    if (solver.info() != Eigen::Success) continue;
    const Vector6 pivots = solver.matrixLLT().diagonal();
    if (!(pivots.minCoeff() > 1e-4 * pivots.maxCoeff())) continue;
    const Vector6 c = solver.solve(rhs);
    double rss = 0;
    for (int k = 0; k < n; ++k) rss += (z[k] - rows[k].dot(c)) * (z[k] - rows[k].dot(c));
    const int dof = n - 6;
    const double median_ratio = std::pow(1.0 - 2.0 / (9.0 * dof), 3);
    if (std::isfinite(rss)) scaled.push_back(rss / dof / median_ratio);
  }
  if (scaled.empty()) return 0.0;
  std::nth_element(scaled.begin(), scaled.begin() + scaled.size() / 2, scaled.end());
  return std::sqrt(scaled[scaled.size() / 2]);
}

}  // namespace surfreg

// The joint problem of a series (registration/series_internal.h): the
// covariance of the pairs' errors, the stacked residual, its Ceres solve
// and the joint covariance.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "registration/series_internal.h"
#include "registration/solvers.h"

namespace surfreg::series_internal {
namespace {

using RowMatrix6d = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

// (ω, t) about c ↦ the same motion about c + d: t + ω × d.
Matrix6d MoveCentre(const Eigen::Vector3d& d) {
  Matrix6d s = Matrix6d::Identity();
  s.block<3, 3>(3, 0) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;  // −[d]×
  return s;
}

// A factor F with F Fᵀ = M: the symmetric square root in units where
// rotations (times `radius`) weigh as translations, so that two pairs'
// factors of similar covariances are alike.
Matrix6d Factor(const Matrix6d& m, double radius) {
  Eigen::Matrix<double, 6, 1> d;
  d << radius, radius, radius, 1, 1, 1;
  const Matrix6d scaled = d.asDiagonal() * m * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(0.5 * (scaled + scaled.transpose()));
  const Eigen::Matrix<double, 6, 1> root = eigen.eigenvalues().cwiseMax(0).cwiseSqrt();
  const Matrix6d f = eigen.eigenvectors() * root.asDiagonal() * eigen.eigenvectors().transpose();
  return d.cwiseInverse().asDiagonal() * f;
}

// δ of one edge (series_internal.h SolveJoint): the relative motion the
// epochs' motions imply, X_r⁻¹ X_m with X(p) = R(ω)(p − g) + g + s, against
// the pair's own, as the rotation vector of their difference and the
// difference of where they take the pair's centre.
struct PairResidual {
  Eigen::Vector3d reference_centroid, moving_centroid, centre;
  Eigen::Matrix3d pair_rotation;
  Eigen::Vector3d pair_shift;

  template <typename T>
  bool operator()(const T* reference_motion, const T* moving_motion, T* residual) const {
    using Vector3 = Eigen::Matrix<T, 3, 1>;
    using Matrix3 = Eigen::Matrix<T, 3, 3>;
    Matrix3 r_ref, r_mov;
    ceres::AngleAxisToRotationMatrix(reference_motion, ceres::ColumnMajorAdapter3x3(r_ref.data()));
    ceres::AngleAxisToRotationMatrix(moving_motion, ceres::ColumnMajorAdapter3x3(r_mov.data()));
    const Vector3 g_ref = reference_centroid.cast<T>(), g_mov = moving_centroid.cast<T>(),
                  c = centre.cast<T>();
    const Vector3 s_ref(reference_motion[3], reference_motion[4], reference_motion[5]);
    const Vector3 s_mov(moving_motion[3], moving_motion[4], moving_motion[5]);
    // Where the moving epoch's motion takes c, then back by the reference's.
    const Vector3 in_common = r_mov * (c - g_mov) + g_mov + s_mov;
    const Vector3 in_reference = r_ref.transpose() * (in_common - g_ref - s_ref) + g_ref;
    const Matrix3 error = r_ref.transpose() * r_mov * pair_rotation.transpose().cast<T>();
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(error.data()), residual);
    Eigen::Map<Vector3>(residual + 3) = in_reference - c - pair_shift.cast<T>();
    return true;
  }
};
using PairCost = ceres::AutoDiffCostFunction<PairResidual, 6, 6, 6>;

// All edges' δ stacked and whitened, r = W δ (WᵀW = C⁺): one residual
// block over every epoch's parameters, since the edges' errors correlate.
class StackedCost : public ceres::CostFunction {
 public:
  StackedCost(const std::vector<Edge>& edges, const std::vector<Eigen::Vector3d>& centroids,
              Eigen::MatrixXd whitening)
      : edges_(edges), whitening_(std::move(whitening)) {
    for (const Edge& edge : edges) {
      auto* residual = new PairResidual;
      residual->reference_centroid = centroids[edge.reference];
      residual->moving_centroid = centroids[edge.moving];
      residual->centre = edge.centre;
      residual->pair_rotation = edge.rotation;
      residual->pair_shift = edge.shift;
      pairs_.emplace_back(new PairCost(residual));
    }
    set_num_residuals(static_cast<int>(whitening_.rows()));
    for (std::size_t e = 0; e < centroids.size(); ++e)
      mutable_parameter_block_sizes()->push_back(6);
  }

  const Eigen::MatrixXd& whitening() const { return whitening_; }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int count = static_cast<int>(edges_.size());
    Eigen::VectorXd delta(6 * count);
    std::vector<RowMatrix6d> d_reference(count), d_moving(count);
    for (int k = 0; k < count; ++k) {
      const double* blocks[2] = {parameters[edges_[k].reference], parameters[edges_[k].moving]};
      double* pair_jacobians[2] = {d_reference[k].data(), d_moving[k].data()};
      if (!pairs_[k]->Evaluate(blocks, delta.data() + 6 * k, jacobians ? pair_jacobians : nullptr))
        return false;
    }
    Eigen::Map<Eigen::VectorXd>(residuals, num_residuals()) = whitening_ * delta;
    if (jacobians == nullptr) return true;
    for (std::size_t b = 0; b < parameter_block_sizes().size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>> out(jacobians[b],
                                                                                num_residuals(), 6);
      out.setZero();
      for (int k = 0; k < count; ++k) {
        const auto columns = whitening_.middleCols<6>(6 * k);
        if (edges_[k].reference == static_cast<int>(b)) out += columns * d_reference[k];
        if (edges_[k].moving == static_cast<int>(b)) out += columns * d_moving[k];
      }
    }
    return true;
  }

 private:
  const std::vector<Edge>& edges_;
  Eigen::MatrixXd whitening_;
  std::vector<std::unique_ptr<PairCost>> pairs_;
};

// W with WᵀW = C⁺ (Jacobi-scaled eigen-decomposition; directions of no
// variance, locked parameters, carry no information).
Eigen::MatrixXd InverseRoot(const Eigen::MatrixXd& c) {
  const Eigen::Index n = c.rows();
  Eigen::VectorXd scale(n);
  for (Eigen::Index k = 0; k < n; ++k) scale[k] = c(k, k) > 0 ? 1 / std::sqrt(c(k, k)) : 0;
  const Eigen::MatrixXd scaled = scale.asDiagonal() * c * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (scaled + scaled.transpose()));
  const double largest = eigen.eigenvalues().maxCoeff();
  Eigen::VectorXd inverse_root = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double value = eigen.eigenvalues()[k];
    if (value > 1e-12 * largest) inverse_root[k] = 1 / std::sqrt(value);
  }
  return inverse_root.asDiagonal() * eigen.eigenvectors().transpose() * scale.asDiagonal();
}

// (Jᵀ J)⁻¹ over the free parameters of every epoch but the reference, J the
// whitened residuals' Jacobian; per epoch its block (NaN where a null
// direction of the information moves the epoch). With `alternatives`
// (other covariances the pairs' errors may have), each epoch's block is the
// largest of the estimate's covariance under each, P Jᵀ W C Wᵀ J P with
// P = (Jᵀ J)⁻¹ (a sandwich): the block whose variances exceed the model's
// most, summed relative to the model's.
std::vector<Matrix6d> JointCovariance(const StackedCost& cost,
                                      const std::vector<std::array<double, 6>>& theta,
                                      int reference, const std::array<bool, 6>& free,
                                      const std::vector<Eigen::MatrixXd>& alternatives) {
  const int n = static_cast<int>(theta.size());
  std::vector<int> column(6 * n, -1);
  int size = 0;
  for (int e = 0; e < n; ++e) {
    for (int k = 0; k < 6; ++k) {
      if (e != reference && free[k]) column[6 * e + k] = size++;
    }
  }
  std::vector<Matrix6d> covariance(n, Matrix6d::Zero());
  if (size == 0) return covariance;
  const int rows = cost.num_residuals();
  std::vector<const double*> parameters;
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>> blocks(n);
  std::vector<double*> jacobians;
  for (int e = 0; e < n; ++e) {
    parameters.push_back(theta[e].data());
    blocks[e].resize(rows, 6);
    jacobians.push_back(blocks[e].data());
  }
  Eigen::VectorXd residuals(rows);
  cost.Evaluate(parameters.data(), residuals.data(), jacobians.data());
  Eigen::MatrixXd j(rows, size);
  for (int e = 0; e < n; ++e) {
    for (int k = 0; k < 6; ++k) {
      if (column[6 * e + k] >= 0) j.col(column[6 * e + k]) = blocks[e].col(k);
    }
  }
  const Eigen::MatrixXd information = j.transpose() * j;
  Eigen::VectorXd scale(size);
  for (int k = 0; k < size; ++k)
    scale[k] = information(k, k) > 0 ? 1 / std::sqrt(information(k, k)) : 0;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scale.asDiagonal() * information *
                                                       scale.asDiagonal());
  const double largest = eigen.eigenvalues().maxCoeff();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(size);
  std::vector<bool> undetermined(size, false);
  for (int k = 0; k < size; ++k) {
    undetermined[k] = scale[k] == 0;
    if (eigen.eigenvalues()[k] > 1e-12 * largest) {
      inverse[k] = 1 / eigen.eigenvalues()[k];
      continue;
    }
    for (int i = 0; i < size; ++i) {
      if (std::fabs(eigen.eigenvectors()(i, k)) > 1e-6) undetermined[i] = true;
    }
  }
  const Eigen::MatrixXd joint = scale.asDiagonal() * eigen.eigenvectors() * inverse.asDiagonal() *
                                eigen.eigenvectors().transpose() * scale.asDiagonal();
  std::vector<Eigen::MatrixXd> candidates;
  if (!alternatives.empty()) {
    const Eigen::MatrixXd lever = cost.whitening().transpose() * j * joint;  // Wᵀ J P
    for (const Eigen::MatrixXd& c : alternatives) candidates.push_back(lever.transpose() * c * lever);
  }
  const auto block_of = [&](const Eigen::MatrixXd& full, int e) {
    Matrix6d block = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) {
      for (int k = 0; k < 6; ++k) {
        if (column[6 * e + i] >= 0 && column[6 * e + k] >= 0)
          block(i, k) = full(column[6 * e + i], column[6 * e + k]);
      }
    }
    return block;
  };
  for (int e = 0; e < n; ++e) {
    bool unknown = false;
    for (int i = 0; i < 6; ++i) {
      if (column[6 * e + i] >= 0) unknown = unknown || undetermined[column[6 * e + i]];
    }
    covariance[e] = block_of(joint, e);
    double most = 0;
    for (const Eigen::MatrixXd& candidate : candidates) {
      const Matrix6d block = block_of(candidate, e);
      double excess = 0;
      for (int k = 0; k < 6; ++k) {
        if (covariance[e](k, k) > 0) excess += block(k, k) / covariance[e](k, k) - 1;
      }
      if (excess > most) most = excess, covariance[e] = block;
    }
    if (unknown) covariance[e].setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  return covariance;
}

}  // namespace

Eigen::MatrixXd EdgeCovariance(const std::vector<Edge>& edges,
                               const std::vector<Eigen::Vector3d>& centroids,
                               const Footprints& footprints, double radius) {
  const int count = static_cast<int>(edges.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(6 * count, 6 * count);
  std::vector<double> area(count);
  for (int k = 0; k < count; ++k) area[k] = footprints.Count({edges[k].reference, edges[k].moving});
  for (int e = 0; e < static_cast<int>(centroids.size()); ++e) {
    // The edges at e, its role's sign in each, and a factor of its half of
    // the edge's covariance aligned with the others' at e's centroid.
    std::vector<int> at;
    std::vector<double> sign;
    std::vector<Matrix6d> factor;
    for (int k = 0; k < count; ++k) {
      if (edges[k].reference != e && edges[k].moving != e) continue;
      at.push_back(k);
      sign.push_back(edges[k].moving == e ? 1.0 : -1.0);
      const Matrix6d to_epoch = MoveCentre(centroids[e] - edges[k].centre);
      const Matrix6d half = to_epoch * (0.5 * edges[k].covariance) * to_epoch.transpose();
      factor.push_back(MoveCentre(edges[k].centre - centroids[e]) * Factor(half, radius));
    }
    for (std::size_t a = 0; a < at.size(); ++a) {
      for (std::size_t b = 0; b < at.size(); ++b) {
        const int p = at[a], q = at[b];
        double shared = 1;
        if (p != q) {
          const int other_p = edges[p].reference == e ? edges[p].moving : edges[p].reference;
          const int other_q = edges[q].reference == e ? edges[q].moving : edges[q].reference;
          const double both = footprints.Count({e, other_p, other_q});
          shared = area[p] > 0 && area[q] > 0 ? both / std::sqrt(area[p] * area[q]) : 0;
        }
        c.block<6, 6>(6 * p, 6 * q) +=
            sign[a] * sign[b] * shared * factor[a] * factor[b].transpose();
      }
    }
  }
  return c;
}

JointSolution SolveJoint(const std::vector<Edge>& edges, const Eigen::MatrixXd& edge_covariance,
                         const std::vector<Eigen::Vector3d>& centroids,
                         std::vector<std::array<double, 6>> start, int reference,
                         const std::array<bool, 6>& free, int threads,
                         const std::vector<Eigen::MatrixXd>& alternatives) {
  JointSolution solution;
  solution.theta = std::move(start);
  const int n = static_cast<int>(centroids.size());
  // Owned by the problem; kept for the covariance.
  auto* cost = new StackedCost(edges, centroids, InverseRoot(edge_covariance));
  ceres::Problem problem;
  std::vector<int> locked;
  for (int k = 0; k < 6; ++k) {
    if (!free[k]) locked.push_back(k);
  }
  std::vector<double*> blocks;
  for (int e = 0; e < n; ++e) blocks.push_back(solution.theta[e].data());
  problem.AddResidualBlock(cost, nullptr, blocks);
  for (int e = 0; e < n; ++e) {
    if (e == reference || locked.size() == 6) {
      problem.SetParameterBlockConstant(blocks[e]);
    } else if (!locked.empty()) {
      problem.SetManifold(blocks[e], new ceres::SubsetManifold(6, locked));
    }
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-15;
  options.gradient_tolerance = 1e-15;
  options.parameter_tolerance = 1e-14;
  options.num_threads = CeresThreads(threads);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  solution.iterations = static_cast<int>(summary.iterations.size());
  solution.converged = summary.termination_type == ceres::CONVERGENCE;
  solution.message = summary.message;
  solution.chi2 = 2 * summary.final_cost;
  int rank = 0, parameters = 0;
  const Eigen::MatrixXd& w = cost->whitening();
  for (Eigen::Index r = 0; r < w.rows(); ++r) rank += w.row(r).squaredNorm() > 0;
  for (int e = 0; e < n; ++e)
    parameters += e == reference ? 0 : 6 - static_cast<int>(locked.size());
  solution.dof = rank - parameters;
  solution.covariance = JointCovariance(*cost, solution.theta, reference, free, alternatives);
  return solution;
}

bool Whitening(const Matrix6d& covariance, const std::array<bool, 6>& free, Matrix6d* whitening) {
  Matrix6d sigma = covariance;
  for (int k = 0; k < 6; ++k) {
    if (!free[k]) {
      sigma.row(k).setZero();
      sigma.col(k).setZero();
    }
  }
  if (!sigma.allFinite() || !(sigma.diagonal().maxCoeff() > 0)) return false;
  *whitening = InverseRoot(sigma);
  return whitening->allFinite();
}

}  // namespace surfreg::series_internal

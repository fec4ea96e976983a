#pragma once
// The joint problem of a series (registration/series.h), apart from the
// orchestration: the epochs' footprints, the covariance of the pairs'
// errors, and the solve. Internal to registration/.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "measure/surface.h"

namespace surfreg::series_internal {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Every epoch's footprint on one occupancy grid (SeriesOverlaps' grid).
struct Footprints {
  std::vector<std::vector<uint8_t>> covered;  // per epoch, per cell: 1 where it has samples
  double Count(std::initializer_list<int> epochs) const;  // cells all of `epochs` cover
};
Footprints EpochFootprints(const std::vector<Surface>& epochs);
// SeriesOverlaps from the footprints.
Eigen::MatrixXd Overlaps(const Footprints& footprints);

// One used pair, in the joint problem's local frame (about a common origin):
// `moving` aligned onto `reference` by a motion whose rotation is `rotation`
// and which shifts `centre` (the moving epoch's centroid as the pair's
// alignment took it) by `shift`; `covariance` of (ω, shift) from that
// alignment (locked rows zero).
struct Edge {
  int reference = 0, moving = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  Matrix6d covariance = Matrix6d::Zero();
};

// The covariance of the edges' errors stacked (6E × 6E). A pair's error is
// the difference of its two epochs' apparent motions over their overlap
// (each epoch's own sampling and noise seen as a motion), each half of the
// pair's covariance. An epoch's apparent motions over two of its pairs'
// overlaps correlate as much as the overlaps share area (|O₁ ∩ O₂| /
// √(|O₁| |O₂|)), with the sign of its role: along a chain, where an epoch is
// moving in one pair and reference in the next, its share cancels. Treating
// the pairs as independent instead gives σ too small wherever epochs overlap
// several others (1.5 × on repeat surveys, tests/bench/series_bench.py).
// `centroids`: the epochs' (local frame); `radius`: the lever that weighs
// rotations with translations.
Eigen::MatrixXd EdgeCovariance(const std::vector<Edge>& edges,
                               const std::vector<Eigen::Vector3d>& centroids,
                               const Footprints& footprints, double radius);

struct JointSolution {
  std::vector<std::array<double, 6>> theta;  // per epoch: ω, then the centroid's shift
  std::vector<Matrix6d> covariance;  // per epoch (zeros: reference, locked; NaN: undetermined)
  int iterations = 0;
  bool converged = false;
  // δᵀ C⁺ δ at the solution and its degrees of freedom (C's rank less the
  // free parameters): about equal when C describes the pairs' errors.
  double chi2 = 0;
  int dof = 0;
  std::string message;
};

// Minimizes ½ δᵀ C⁺ δ over every epoch's motion about its centroid (the
// reference's held at 0, locked parameters at their start), δ the edges'
// differences between the relative motion the epochs' motions imply and the
// pair's own, C = EdgeCovariance: one Ceres problem. The covariance is
// (Jᵀ C⁺ J)⁻¹ at the solution; given `alternatives` (other covariances the
// pairs' errors may have), each epoch's block is the largest of the
// estimate's covariance under each and under C (a sandwich).
JointSolution SolveJoint(const std::vector<Edge>& edges, const Eigen::MatrixXd& edge_covariance,
                         const std::vector<Eigen::Vector3d>& centroids,
                         std::vector<std::array<double, 6>> start, int reference,
                         const std::array<bool, 6>& free, int threads,
                         const std::vector<Eigen::MatrixXd>& alternatives = {});

// W with WᵀW = Σ⁺ on the free parameters (Jacobi-scaled: radians and data
// units differ by orders of magnitude); false when Σ is not finite there.
bool Whitening(const Matrix6d& covariance, const std::array<bool, 6>& free, Matrix6d* whitening);

}  // namespace surfreg::series_internal

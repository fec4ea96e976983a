// Joint alignment of a series of surveys (registration/series.h): the
// pairwise alignments over the overlap graph, then one Ceres problem over
// every epoch's motion with each pair's cost to second order.
#include "registration/series.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <sstream>
#include <string>

#include "measure/input_error.h"
#include "measure/measures.h"
#include "registration/align.h"
#include "registration/rigid_motion.h"

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string Name(const std::vector<Surface>& epochs, int e) {
  const std::string& source = epochs[e].source;
  return "epoch " + std::to_string(e) + (source.empty() ? "" : " (" + source + ")");
}

std::string PieceText(const std::vector<int>& piece) {
  std::string text = "{";
  for (std::size_t k = 0; k < piece.size(); ++k) text += (k ? ", " : "") + std::to_string(piece[k]);
  return text + "}";
}

void RefuseIfApart(const std::vector<std::vector<int>>& pieces, const std::string& when) {
  if (pieces.size() < 2) return;
  std::string text = "the series falls apart" + when + " into ";
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    text += (k == 0 ? "" : k + 1 == pieces.size() ? " and " : ", ") + PieceText(pieces[k]);
  }
  throw InputError(text + ": no pair joins them (give `pairs`, or lower min_overlap)");
}

void Validate(const std::vector<Surface>& epochs, const SeriesOptions& options) {
  const int n = static_cast<int>(epochs.size());
  if (n < 2) throw InputError("series: at least two epochs are needed, got " + std::to_string(n));
  if (options.reference < 0 || options.reference >= n) {
    throw InputError("series: reference " + std::to_string(options.reference) +
                     " is not an epoch (0 to " + std::to_string(n - 1) + ")");
  }
  if (!(options.min_overlap > 0 && options.min_overlap <= 1)) {
    throw InputError("series: min_overlap must be in (0, 1], got " +
                     std::to_string(options.min_overlap));
  }
  for (const auto& [a, b] : options.pairs) {
    if (a < 0 || a >= n || b < 0 || b >= n || a == b) {
      throw InputError("series: pair " + std::to_string(a) + "-" + std::to_string(b) +
                       " does not name two different epochs (0 to " + std::to_string(n - 1) + ")");
    }
  }
  const AlignOptions& align = options.align;
  if (align.initial_reference_from_moving ||
      align.initial_rotation != std::array<double, 3>{0, 0, 0} ||
      align.initial_translation != std::array<double, 3>{0, 0, 0}) {
    throw InputError(
        "series: an initial motion applies to one pair; the series starts from the inputs");
  }
  std::string error;
  if (!align.IsValid(&error)) throw InputError("series: " + error);
  for (int e = 0; e < n; ++e) {
    if (epochs[e].size() < 3)
      throw InputError("series: " + Name(epochs, e) + " has fewer than 3 samples");
  }
}

// The edges: the user's, or every pair overlapping enough. An epoch with no
// edge is named with its best overlap.
std::vector<SeriesPair> Edges(const std::vector<Surface>& epochs, const SeriesOptions& options) {
  const int n = static_cast<int>(epochs.size());
  const Eigen::MatrixXd overlap = SeriesOverlaps(epochs);
  std::vector<SeriesPair> pairs;
  if (!options.pairs.empty()) {
    for (const auto& [a, b] : options.pairs) {
      SeriesPair pair;
      pair.reference = a;
      pair.moving = b;
      pair.overlap = overlap(a, b);
      pairs.push_back(std::move(pair));
    }
  } else {
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        if (overlap(i, j) < options.min_overlap) continue;
        SeriesPair pair;
        pair.reference = i;
        pair.moving = j;
        pair.overlap = overlap(i, j);
        pairs.push_back(std::move(pair));
      }
    }
    for (int e = 0; e < n; ++e) {
      const bool joined = std::any_of(pairs.begin(), pairs.end(), [e](const SeriesPair& p) {
        return p.reference == e || p.moving == e;
      });
      if (joined) continue;
      int best = e == 0 ? 1 : 0;
      for (int k = 0; k < n; ++k) {
        if (k != e && overlap(e, k) > overlap(e, best)) best = k;
      }
      std::ostringstream text;
      text.precision(2);
      text << "series: " << Name(epochs, e) << " overlaps no other by min_overlap "
           << options.min_overlap << " (at most " << overlap(e, best) << ", with epoch " << best
           << ")";
      throw InputError(text.str());
    }
  }
  std::vector<std::pair<int, int>> links;
  for (const SeriesPair& p : pairs) links.emplace_back(p.reference, p.moving);
  RefuseIfApart(GraphPieces(n, links), "");
  return pairs;
}

// The information ½ δᵀ Σ⁻¹ δ as a whitening W (WᵀW = Σ⁺): directions of
// zero variance (locked parameters) carry no information. False when Σ is
// not finite on the free parameters.
bool Whitening(const Matrix6d& covariance, const std::array<bool, 6>& free, Matrix6d* whitening) {
  Matrix6d sigma = covariance;
  for (int k = 0; k < 6; ++k) {
    if (!free[k]) {
      sigma.row(k).setZero();
      sigma.col(k).setZero();
    }
  }
  if (!sigma.allFinite()) return false;
  // Jacobi scaling first: radians and data units differ by orders of magnitude.
  Eigen::Matrix<double, 6, 1> scale;
  for (int k = 0; k < 6; ++k) scale[k] = sigma(k, k) > 0 ? 1 / std::sqrt(sigma(k, k)) : 0;
  const Matrix6d scaled = scale.asDiagonal() * sigma * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(scaled);
  const double largest = eigen.eigenvalues().maxCoeff();
  if (!(largest > 0)) return false;
  Eigen::Matrix<double, 6, 1> inverse_root;
  for (int k = 0; k < 6; ++k) {
    const double value = eigen.eigenvalues()[k];
    inverse_root[k] = value > 1e-12 * largest ? 1 / std::sqrt(value) : 0;
  }
  *whitening = inverse_root.asDiagonal() * eigen.eigenvectors().transpose() * scale.asDiagonal();
  return whitening->allFinite();
}

// One edge's residual W δ: δ the difference between the relative motion
// the two epochs' motions imply (reference_from_moving = X_r⁻¹ X_m) and the
// pair's own, as its rotation vector and the shift of the pair's centre.
// Each epoch's motion: X(p) = R(ω)(p − g) + g + s, all about a common origin.
struct PairResidual {
  Eigen::Vector3d reference_centroid, moving_centroid, centre;
  Eigen::Matrix3d pair_rotation;
  Eigen::Vector3d pair_shift;
  Matrix6d whitening;

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
    Eigen::Matrix<T, 6, 1> delta;
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(error.data()), delta.data());
    delta.template tail<3>() = in_reference - c - pair_shift.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = whitening.cast<T>() * delta;
    return true;
  }
};

Eigen::Vector3d Centroid(const Surface& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < s.size(); ++k) sum += Eigen::Vector3d(s.xy[k].x, s.xy[k].y, s.z[k]);
  return sum / static_cast<double>(s.size()) +
         Eigen::Vector3d(s.origin[0], s.origin[1], s.origin[2]);
}

// The epochs' motions along a spanning tree of the used edges from the
// reference (largest overlap first), each composed from the pairs' own.
std::vector<Rigid3d> ChainedStart(int n, int reference, const std::vector<SeriesPair>& pairs) {
  std::vector<Rigid3d> motion(n);
  std::vector<bool> known(n, false);
  known[reference] = true;
  using Entry = std::pair<double, int>;  // overlap, pair
  std::priority_queue<Entry> frontier;
  const auto push_from = [&](int epoch) {
    for (int k = 0; k < static_cast<int>(pairs.size()); ++k) {
      const SeriesPair& p = pairs[k];
      if (p.used && (p.reference == epoch || p.moving == epoch)) frontier.push({p.overlap, k});
    }
  };
  push_from(reference);
  while (!frontier.empty()) {
    const SeriesPair& p = pairs[frontier.top().second];
    frontier.pop();
    if (known[p.reference] == known[p.moving]) continue;
    const Rigid3d& reference_from_moving = p.pairwise.reference_from_moving;
    if (known[p.reference]) {
      motion[p.moving] = motion[p.reference] * reference_from_moving;
      known[p.moving] = true;
      push_from(p.moving);
    } else {
      motion[p.reference] = motion[p.moving] * reference_from_moving.Inverse();
      known[p.reference] = true;
      push_from(p.reference);
    }
  }
  return motion;
}

// The joint covariance: the inverse of the information Σ JᵀJ of the edges'
// whitened residuals at the solution, over the free parameters of every
// epoch but the reference; its 6 × 6 block per epoch (zeros for the
// reference and locked parameters). An epoch that a null direction of the
// information moves gets NaN.
std::vector<Matrix6d> JointCovariance(ceres::Problem& problem, int n, const SeriesOptions& options,
                                      std::vector<std::array<double, 6>>& theta) {
  std::vector<int> column(6 * n, -1);
  int size = 0;
  for (int e = 0; e < n; ++e) {
    for (int k = 0; k < 6; ++k) {
      if (e != options.reference && options.align.free[k]) column[6 * e + k] = size++;
    }
  }
  std::vector<Matrix6d> covariance(n, Matrix6d::Zero());
  if (size == 0) return covariance;
  const auto epoch_of = [&theta](const double* block) {
    for (std::size_t e = 0; e < theta.size(); ++e) {
      if (theta[e].data() == block) return static_cast<int>(e);
    }
    return -1;
  };
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(size, size);
  std::vector<ceres::ResidualBlockId> blocks;
  problem.GetResidualBlocks(&blocks);
  for (ceres::ResidualBlockId id : blocks) {
    std::vector<double*> parameters;
    problem.GetParameterBlocksForResidualBlock(id, &parameters);
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> jacobian[2];
    double residual[6];
    double* jacobians[2] = {jacobian[0].data(), jacobian[1].data()};
    problem.GetCostFunctionForResidualBlock(id)->Evaluate(parameters.data(), residual, jacobians);
    const int epochs[2] = {epoch_of(parameters[0]), epoch_of(parameters[1])};
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        const Matrix6d block = jacobian[a].transpose() * jacobian[b];
        for (int i = 0; i < 6; ++i) {
          for (int j = 0; j < 6; ++j) {
            const int row = column[6 * epochs[a] + i], col = column[6 * epochs[b] + j];
            if (row >= 0 && col >= 0) information(row, col) += block(i, j);
          }
        }
      }
    }
  }
  Eigen::VectorXd scale(size);
  for (int k = 0; k < size; ++k)
    scale[k] = information(k, k) > 0 ? 1 / std::sqrt(information(k, k)) : 0;
  const Eigen::MatrixXd scaled = scale.asDiagonal() * information * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  const double largest = eigen.eigenvalues().maxCoeff();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(size);
  std::vector<bool> undetermined(size, false);
  for (int k = 0; k < size; ++k) {
    if (eigen.eigenvalues()[k] > 1e-12 * largest) {
      inverse[k] = 1 / eigen.eigenvalues()[k];
      continue;
    }
    for (int i = 0; i < size; ++i)
      undetermined[i] = undetermined[i] || std::fabs(eigen.eigenvectors()(i, k)) > 1e-6;
  }
  for (int k = 0; k < size; ++k) undetermined[k] = undetermined[k] || scale[k] == 0;
  const Eigen::MatrixXd joint = scale.asDiagonal() * eigen.eigenvectors() * inverse.asDiagonal() *
                                eigen.eigenvectors().transpose() * scale.asDiagonal();
  for (int e = 0; e < n; ++e) {
    bool unknown = false;
    for (int i = 0; i < 6; ++i) {
      const int row = column[6 * e + i];
      if (row < 0) continue;
      unknown = unknown || undetermined[row];
      for (int j = 0; j < 6; ++j) {
        const int col = column[6 * e + j];
        if (col >= 0) covariance[e](i, j) = joint(row, col);
      }
    }
    if (unknown) covariance[e].setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  return covariance;
}

}  // namespace

SeriesResult AlignSeries(const std::vector<Surface>& epochs, const SeriesOptions& options) {
  const Clock::time_point start = Clock::now();
  Validate(epochs, options);
  const int n = static_cast<int>(epochs.size());
  const auto stage = [&options](const std::string& text) {
    if (options.on_stage) options.on_stage(text);
  };
  SeriesResult result;
  result.reference = options.reference;
  result.pairs = Edges(epochs, options);

  // 2. Each pair on its own.
  const Clock::time_point pairwise_start = Clock::now();
  for (std::size_t k = 0; k < result.pairs.size(); ++k) {
    SeriesPair& p = result.pairs[k];
    stage("aligning pair " + std::to_string(p.reference) + "-" + std::to_string(p.moving) + " (" +
          std::to_string(k + 1) + "/" + std::to_string(result.pairs.size()) + ")");
    p.pairwise = Align(epochs[p.reference], epochs[p.moving], options.align);
    Matrix6d unused;
    if (p.pairwise.verdict != Verdict::kConvergedImproved &&
        p.pairwise.verdict != Verdict::kConvergedNotImproved) {
      p.reason = std::string("its alignment is ") + VerdictName(p.pairwise.verdict) + ": " +
                 p.pairwise.verdict_reason;
    } else if (!Whitening(p.pairwise.covariance, options.align.free, &unused)) {
      p.reason = "its alignment has no covariance";
    } else {
      p.used = true;
    }
  }
  result.pairwise_seconds = Since(pairwise_start);
  std::vector<std::pair<int, int>> used_links;
  for (const SeriesPair& p : result.pairs) {
    if (p.used) used_links.emplace_back(p.reference, p.moving);
  }
  RefuseIfApart(GraphPieces(n, used_links), " once the pairs that did not align are left out");

  // 3. The joint problem, about the reference's centroid (small numbers).
  stage("joint solve");
  const Eigen::Vector3d origin = Centroid(epochs[options.reference]);
  const Rigid3d to_local{Eigen::Matrix3d::Identity(), -origin},
      from_local{Eigen::Matrix3d::Identity(), origin};
  std::vector<Eigen::Vector3d> centroid(n);
  for (int e = 0; e < n; ++e) centroid[e] = Centroid(epochs[e]) - origin;
  const std::vector<Rigid3d> start_motion = ChainedStart(n, options.reference, result.pairs);
  std::vector<std::array<double, 6>> theta(n);
  for (int e = 0; e < n; ++e) {
    const Rigid3d local = to_local * start_motion[e] * from_local;
    const Eigen::Vector3d w = local.RotationVector(), s = local.ShiftOf(centroid[e]);
    theta[e] = {w[0], w[1], w[2], s[0], s[1], s[2]};
  }
  ceres::Problem problem;
  std::vector<int> locked;
  for (int k = 0; k < 6; ++k) {
    if (!options.align.free[k]) locked.push_back(k);
  }
  for (int e = 0; e < n; ++e) {
    problem.AddParameterBlock(theta[e].data(), 6);
    if (e == options.reference || locked.size() == 6) {
      problem.SetParameterBlockConstant(theta[e].data());
    } else if (!locked.empty()) {
      problem.SetManifold(theta[e].data(), new ceres::SubsetManifold(6, locked));
    }
  }
  for (const SeriesPair& p : result.pairs) {
    if (!p.used) continue;
    auto* residual = new PairResidual;
    residual->reference_centroid = centroid[p.reference];
    residual->moving_centroid = centroid[p.moving];
    residual->centre =
        Eigen::Vector3d(p.pairwise.centre[0], p.pairwise.centre[1], p.pairwise.centre[2]) - origin;
    const Rigid3d local = to_local * p.pairwise.reference_from_moving * from_local;
    residual->pair_rotation = local.rotation;
    residual->pair_shift = local.ShiftOf(residual->centre);
    Whitening(p.pairwise.covariance, options.align.free, &residual->whitening);
    auto* cost = new ceres::AutoDiffCostFunction<PairResidual, 6, 6, 6>(residual);
    problem.AddResidualBlock(cost, nullptr, theta[p.reference].data(), theta[p.moving].data());
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  if (n > 30) solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = 200;
  solver.function_tolerance = 1e-15;
  solver.gradient_tolerance = 1e-15;
  solver.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.termination = summary.message;

  const std::vector<Matrix6d> covariance = JointCovariance(problem, n, options, theta);
  const bool converged = summary.termination_type == ceres::CONVERGENCE;

  // 4. Each epoch's motion and σ, each pair's measures and misclosure.
  std::vector<Rigid3d> motion(n);
  for (int e = 0; e < n; ++e) {
    const Eigen::Vector3d w(theta[e][0], theta[e][1], theta[e][2]),
        s(theta[e][3], theta[e][4], theta[e][5]);
    motion[e] = from_local * Rigid3d::RotationAbout(w, centroid[e], s) * to_local;
    SeriesEpoch& epoch = result.epochs.emplace_back();
    epoch.matrix = motion[e].ToMatrix();
    for (int k = 0; k < 3; ++k) {
      epoch.centre[k] = centroid[e][k] + origin[k];
      epoch.translation[k] = s[k];
    }
    epoch.euler_deg = EulerDegrees(motion[e].rotation);
    epoch.covariance = covariance[e];
    for (int k = 0; k < 6; ++k) epoch.stddev[k] = std::sqrt(covariance[e](k, k));
  }
  MeasureOptions measure;
  measure.domain = options.align.domain;
  measure.threads = options.align.num_threads;
  measure.allow_empty_overlap = true;
  for (SeriesPair& p : result.pairs) {
    stage("measuring pair " + std::to_string(p.reference) + "-" + std::to_string(p.moving));
    const MeasureReference reference(epochs[p.reference], measure);
    p.before = Measure(reference, epochs[p.moving], measure);
    const Rigid3d joint = motion[p.reference].Inverse() * motion[p.moving];
    p.after = Measure(reference, TransformSurface(epochs[p.moving], joint.ToMatrix()), measure);
    const Rigid3d& own = p.pairwise.reference_from_moving;
    const Eigen::Vector3d c(p.pairwise.centre[0], p.pairwise.centre[1], p.pairwise.centre[2]);
    p.misclosure_deg = (own.Inverse() * joint).RotationVector().norm() * 180 / M_PI;
    p.misclosure_shift = (joint * c - own * c).norm();
    Matrix6d whitening;
    if (Whitening(p.pairwise.covariance, options.align.free, &whitening)) {
      Eigen::Matrix<double, 6, 1> delta;
      delta.head<3>() = (joint * own.Inverse()).RotationVector();
      delta.tail<3>() = joint * c - own * c;
      p.misclosure_chi2 = (whitening * delta).squaredNorm();
    }
    if (!p.used) continue;
    ++result.epochs[p.reference].pairs;
    ++result.epochs[p.moving].pairs;
  }
  for (int e = 0; e < n; ++e) {
    SeriesEpoch& epoch = result.epochs[e];
    if (e == options.reference) {
      epoch.verdict_reason = "the reference epoch";
    } else if (!converged) {
      epoch.verdict = Verdict::kFailed;
      epoch.verdict_reason = "the joint solve did not converge: " + summary.message;
    } else if (!epoch.covariance.allFinite()) {
      epoch.verdict = Verdict::kIllConditioned;
      epoch.verdict_reason = "the pairs do not determine every parameter of its motion";
    } else {
      // Improved when its pairs' mean |dz| at the nodes, together, went down.
      double before = 0, after = 0;
      for (const SeriesPair& p : result.pairs) {
        if (!p.used || (p.reference != e && p.moving != e)) continue;
        before += p.before.rho_d_axial;
        after += p.after.rho_d_axial;
      }
      epoch.verdict =
          after <= before ? Verdict::kConvergedImproved : Verdict::kConvergedNotImproved;
      epoch.verdict_reason = std::to_string(epoch.pairs) + (epoch.pairs == 1 ? " pair" : " pairs") +
                             (after <= before ? ", mean |dz| down" : ", mean |dz| not down");
    }
  }
  result.seconds = Since(start);
  return result;
}

}  // namespace surfreg

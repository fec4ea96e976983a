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
#include <mutex>
#include <queue>
#include <sstream>
#include <string>

#include "measure/input_error.h"
#include "measure/measures.h"
#include "measure/tasks.h"
#include "registration/align.h"
#include "registration/rigid_motion.h"
#include "registration/series_internal.h"

namespace surfreg {
namespace {

using series_internal::Whitening;

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
  throw InputError(text + ": no pair joins them (give 'pairs', or lower min_overlap)");
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
std::vector<SeriesPair> Edges(const std::vector<Surface>& epochs, const SeriesOptions& options,
                              const series_internal::Footprints& footprints) {
  const int n = static_cast<int>(epochs.size());
  const Eigen::MatrixXd overlap = series_internal::Overlaps(footprints);
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

Eigen::Vector3d Centroid(const Surface& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < s.size(); ++k) sum += Eigen::Vector3d(s.xy[k].x, s.xy[k].y, s.z[k]);
  return sum / static_cast<double>(s.size()) +
         Eigen::Vector3d(s.origin[0], s.origin[1], s.origin[2]);
}

// The RMS distance of the samples from their centroid: the lever that
// weighs rotations with translations.
double RmsRadius(const Surface& s) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < s.size(); ++k) mean += Eigen::Vector3d(s.xy[k].x, s.xy[k].y, s.z[k]);
  mean /= static_cast<double>(s.size());
  double sum = 0;
  for (std::size_t k = 0; k < s.size(); ++k)
    sum += (Eigen::Vector3d(s.xy[k].x, s.xy[k].y, s.z[k]) - mean).squaredNorm();
  return std::sqrt(sum / static_cast<double>(s.size()));
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

}  // namespace

int SeriesPairsAtOnce(const std::vector<Surface>& epochs, int pairs, int threads) {
  std::size_t largest = 0;
  for (const Surface& epoch : epochs) largest = std::max(largest, epoch.size());
  return AlignmentsAtOnce(largest, pairs, threads);
}

SeriesResult AlignSeries(const std::vector<Surface>& epochs, const SeriesOptions& options) {
  const Clock::time_point start = Clock::now();
  Validate(epochs, options);
  const int n = static_cast<int>(epochs.size());
  const auto stage = [&options](const std::string& text) {
    if (options.on_stage) options.on_stage(text);
  };
  SeriesResult result;
  result.reference = options.reference;
  const series_internal::Footprints footprints = series_internal::EpochFootprints(epochs);
  result.pairs = Edges(epochs, options, footprints);

  // 2. Each pair on its own. Small pairs run several at a time, each on one
  // thread (an alignment's result does not depend on its thread count, so
  // neither do these): a 6000-point pair keeps two cores far less busy than
  // two such pairs do. One thread each, not a share: a pair's own threads
  // would wait for slots that the pairs beside it hold.
  const Clock::time_point pairwise_start = Clock::now();
  const int pair_count = static_cast<int>(result.pairs.size());
  const int threads = ExecutionFor(options.align.num_threads).threads;
  const int at_once = SeriesPairsAtOnce(epochs, pair_count, threads);
  AlignOptions pair_options = options.align;
  pair_options.num_threads = at_once > 1 ? 1 : threads;
  std::mutex stage_mutex;
  ForEachItem(ExecutionFor(at_once), pair_count, [&](int k) {  // the first failing pair's error, whatever the order
    SeriesPair& p = result.pairs[k];
    {
      std::lock_guard<std::mutex> lock(stage_mutex);
      stage("aligning pair " + std::to_string(p.reference) + "-" + std::to_string(p.moving) + " (" +
            std::to_string(k + 1) + "/" + std::to_string(pair_count) + ")");
    }
    p.pairwise = Align(epochs[p.reference], epochs[p.moving], pair_options);
  });
  for (SeriesPair& p : result.pairs) {
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
  std::vector<series_internal::Edge> edges;
  for (const SeriesPair& p : result.pairs) {
    if (!p.used) continue;
    series_internal::Edge& edge = edges.emplace_back();
    edge.reference = p.reference;
    edge.moving = p.moving;
    edge.centre =
        Eigen::Vector3d(p.pairwise.centre[0], p.pairwise.centre[1], p.pairwise.centre[2]) - origin;
    const Rigid3d local = to_local * p.pairwise.reference_from_moving * from_local;
    edge.rotation = local.rotation;
    edge.shift = local.ShiftOf(edge.centre);
    edge.covariance = p.pairwise.covariance;
    for (int k = 0; k < 6; ++k) {
      if (!options.align.free[k])
        edge.covariance.row(k).setZero(), edge.covariance.col(k).setZero();
    }
  }
  // The pairs' errors: a share `correlated` through their epochs
  // (EdgeCovariance), the rest each pair's own; the share whose residuals
  // fit it (δᵀ C⁻¹ δ closest to its degrees of freedom) is kept.
  const Eigen::MatrixXd shared = series_internal::EdgeCovariance(
      edges, centroid, footprints, RmsRadius(epochs[options.reference]));
  Eigen::MatrixXd separate = Eigen::MatrixXd::Zero(shared.rows(), shared.cols());
  for (std::size_t k = 0; k < edges.size(); ++k)
    separate.block<6, 6>(6 * k, 6 * k) = edges[k].covariance;
  // The share is poorly determined by few loops' residuals: each epoch's σ
  // is the largest the chosen motions have under any of the shares.
  const double kShares[] = {0.0, 0.5, 0.75, 0.88, 0.94};
  std::vector<Eigen::MatrixXd> share_covariances;
  for (const double correlated : kShares)
    share_covariances.push_back(correlated * shared + (1 - correlated) * separate);
  series_internal::JointSolution solution;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < share_covariances.size(); ++s) {
    const double correlated = kShares[s];
    series_internal::JointSolution candidate = series_internal::SolveJoint(
        edges, share_covariances[s], centroid, theta, options.reference, options.align.free,
        ExecutionFor(options.align.num_threads).threads, share_covariances);
    if (candidate.dof <= 0) {  // a tree: every share gives the same motions
      solution = std::move(candidate);
      break;
    }
    const double misfit = std::fabs(std::log(std::max(candidate.chi2, 1e-300) / candidate.dof));
    if (misfit < best) {
      best = misfit;
      solution = std::move(candidate);
      result.pair_correlation = correlated;
    }
  }
  theta = solution.theta;
  const std::vector<Matrix6d>& covariance = solution.covariance;
  const bool converged = solution.converged;
  result.iterations = solution.iterations;
  result.termination = solution.message;

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
  // The pairs' measures side by side as their alignments ran (one thread
  // each when several), their misclosures after.
  MeasureOptions measure;
  measure.domain = options.align.domain;
  measure.threads = at_once > 1 ? 1 : threads;
  measure.allow_empty_overlap = true;
  ForEachItem(ExecutionFor(at_once), pair_count, [&](int k) {
    SeriesPair& p = result.pairs[k];
    {
      std::lock_guard<std::mutex> lock(stage_mutex);
      stage("measuring pair " + std::to_string(p.reference) + "-" + std::to_string(p.moving));
    }
    const MeasureReference reference(epochs[p.reference], measure);
    p.before = Measure(reference, epochs[p.moving], measure);
    const Rigid3d joint = motion[p.reference].Inverse() * motion[p.moving];
    p.after = Measure(reference, TransformSurface(epochs[p.moving], joint.ToMatrix()), measure);
  });
  for (SeriesPair& p : result.pairs) {
    const Rigid3d joint = motion[p.reference].Inverse() * motion[p.moving];
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
      epoch.verdict_reason = "the joint solve did not converge: " + solution.message;
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

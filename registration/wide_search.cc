#include "registration/wide_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "registration/axial_cost.h"
#include "registration/rigid_motion.h"
#include "registration/solvers.h"

namespace surfreg {
namespace {

// The 12 vertices of an icosahedron: rotation axes spread evenly.
std::vector<Eigen::Vector3d> Axes() {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> out;
  for (double a : {-1.0, 1.0}) {
    for (double b : {-g, g}) {
      out.push_back(Eigen::Vector3d(0, a, b).normalized());
      out.push_back(Eigen::Vector3d(a, b, 0).normalized());
      out.push_back(Eigen::Vector3d(b, 0, a).normalized());
    }
  }
  return out;
}

Eigen::Vector3d Mean(const std::vector<Point2>& xy, const std::vector<double>& z) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < xy.size(); ++i) sum += Eigen::Vector3d(xy[i].x, xy[i].y, z[i]);
  return sum / static_cast<double>(xy.size());
}

}  // namespace

WideSearchResult WideSearch(const ReferenceSide& reference, const MovingSide& moving,
                            const std::array<double, 6>& theta0, const AlignOptions& options,
                            double rotation_scale) {
  AlignOptions coarse = options;
  coarse.axial_solver.max_num_iterations = coarse.volume_solver.max_num_iterations = 30;
  coarse.loss = LossKind::kNone;
  coarse.on_iteration = nullptr;
  coarse.on_stage = nullptr;
  SolveContext context;
  context.options = &coarse;
  context.rotation_scale = rotation_scale;
  context.axial.normal_distance = options.normal_distance;

  // Rotations: the start's, and the start's turned by 12° and 24° about
  // twelve evenly spread axes (the basin is about 10° wide). Translations:
  // the start's, and the one that puts the moving centroid on the
  // reference's (for shifts beyond the basin's 20 spacings).
  const Eigen::Matrix3d r0 = RotationMatrix({theta0[0], theta0[1], theta0[2]});
  std::vector<Eigen::Matrix3d> rotations = {r0};
  for (const Eigen::Vector3d& axis : Axes()) {
    for (double degrees : {12.0, 24.0}) {
      rotations.push_back(Eigen::AngleAxisd(degrees * M_PI / 180, axis).matrix() * r0);
    }
  }
  const Eigen::Vector3d centroids = Mean(reference.xy, reference.z) - moving.centroid;
  const Eigen::Vector3d shifts[2] = {Eigen::Vector3d(theta0[3], theta0[4], theta0[5]), centroids};

  struct Candidate {
    std::array<double, 6> theta;
    double mean_square;
    int64_t nodes;
  };
  std::vector<Candidate> ends;
  WideSearchResult result;
  for (const Eigen::Matrix3d& r : rotations) {
    const Eigen::AngleAxisd aa(r);
    const Eigen::Vector3d w = aa.angle() * aa.axis();
    for (const Eigen::Vector3d& t : shifts) {
      const std::array<double, 6> start = {w[0], w[1], w[2], t[0], t[1], t[2]};
      PairState state(reference, moving, options.max_fold_fraction);
      if (!state.Update(start)) continue;
      AxialResiduals at_start;
      ComputeAxialResiduals(state, context.axial, false, &at_start);
      if (at_start.active_count < 10) continue;
      ++result.candidates;
      const SolveResult solved = SolveAxial(state, context, start);
      if (!solved.usable || !state.Update(solved.theta)) continue;
      AxialResiduals end;
      ComputeAxialResiduals(state, context.axial, false, &end);
      if (end.active_count < 10) continue;
      double sum = 0;
      for (std::size_t k = 0; k < end.r.size(); ++k) sum += end.active[k] ? end.r[k] * end.r[k] : 0.0;
      ends.push_back({solved.theta, sum / end.active_weight, end.active_count});
    }
  }
  result.theta = theta0;
  if (ends.empty()) return result;
  // A small overlap can have a small mean gap anywhere: only ends that keep
  // at least half the best overlap compete.
  int64_t most = 0;
  for (const Candidate& c : ends) most = std::max(most, c.nodes);
  double best = std::numeric_limits<double>::infinity();
  for (const Candidate& c : ends) {
    if (2 * c.nodes < most || !(c.mean_square < best)) continue;
    best = c.mean_square;
    result.theta = c.theta;
  }
  result.mean_square_gap = best;
  return result;
}

}  // namespace surfreg

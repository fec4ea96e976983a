// What TrackJaw derives from the parts' registrations (jaw.h): the
// covariance of a part (a clustered sandwich, jaw_internal.h), its
// propagation to the jaw's reported parameters and the path point, the
// default path point, the summary text.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "faces/helical_axis.h"
#include "faces/jaw_internal.h"
#include "registration/align_options.h"
#include "registration/rigid_motion.h"
#include "registration/sandwich.h"
#include "registration/solvers.h"

namespace surfreg {
namespace jaw_internal {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A part's motion as its six parameters about its centre (rigid_motion.h).
struct PartTheta {
  Eigen::Vector3d rotation, shift, centre;
  explicit PartTheta(const JawPartResult& part) : centre(part.centre) {
    const Rigid3d motion = Rigid3d::FromMatrix(part.reference_from_frame);
    rotation = motion.RotationVector();
    shift = motion.ShiftOf(centre);
  }
  Rigid3d At(const double* delta) const {
    return Rigid3d::RotationAbout(rotation + Eigen::Vector3d(delta), centre,
                                  shift + Eigen::Vector3d(delta + 3));
  }
};

using Outputs = Eigen::Matrix<double, 9, 1>;  // Euler (deg), translation, path point

Outputs OutputsOf(const Rigid3d& jaw, const Eigen::Vector3d& p0) {
  Outputs out;
  const std::array<double, 3> euler = EulerDegrees(jaw.rotation);
  out << euler[0], euler[1], euler[2], jaw.translation, jaw * p0;
  return out;
}

}  // namespace

bool GaussNewtonCovariance(const AxialResiduals& residuals, Matrix6d* covariance) {
  *covariance = Matrix6d::Constant(kNaN);
  Matrix6d h = Matrix6d::Zero();
  double sum_squares = 0;
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (!residuals.active[k]) continue;
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> row(residuals.jacobian[k].data());
    h.selfadjointView<Eigen::Lower>().rankUpdate(row);
    sum_squares += residuals.r[k] * residuals.r[k];
  }
  if (residuals.active_count <= 6) return false;
  h = h.selfadjointView<Eigen::Lower>();
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(h);
  const auto& lambda = eigen.eigenvalues();
  // Rank deficient to the tolerance AnalyseInformation (solvers.h) uses.
  if (!(lambda.minCoeff() > 1e-14 * lambda.maxCoeff())) return false;
  const double variance = sum_squares / static_cast<double>(residuals.active_count - 6);
  *covariance = variance * eigen.eigenvectors() * lambda.cwiseInverse().asDiagonal() *
                eigen.eigenvectors().transpose();
  return true;
}

PartCovariance PartSandwichCovariance(PairState& state, const AxialSettings& settings,
                                      double scale) {
  PartCovariance out;
  out.covariance = Matrix6d::Constant(kNaN);
  AxialResiduals residuals;
  ComputeAxialResiduals(state, settings, /*jacobians=*/true, &residuals);
  Matrix6d gauss_newton;
  if (!GaussNewtonCovariance(residuals, &gauss_newton)) return out;
  // The sandwich of the cost minimized (align's, for the axial cost).
  AlignOptions options;  // all six free
  SolveContext context;
  context.options = &options;
  context.axial = settings;
  context.rotation_scale = scale;
  std::array<double, 6> step{};
  for (int i = 0; i < 6; ++i) {
    step[i] = kBreadStepSigmas * std::sqrt(std::max(0.0, gauss_newton(i, i)));
  }
  const SandwichEstimate sandwich = AxialSandwichCovariance(state, context, step);
  out.tiles = sandwich.tiles;
  if (sandwich.ok) {
    out.ok = true;
    out.measured_curvature = true;
    out.covariance = sandwich.covariance;
    return out;
  }
  // The differences failed (no positive definite H: e.g. all residuals 0):
  // the same meat with JᵀJ for H.
  const Matrix6d meat = AxialScoreSpread(state, residuals, 6, &out.tiles);
  if (out.tiles < 12) return out;
  Matrix6d h = Matrix6d::Zero();
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (!residuals.active[k]) continue;
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> row(residuals.jacobian[k].data());
    h.selfadjointView<Eigen::Lower>().rankUpdate(row);
  }
  h = h.selfadjointView<Eigen::Lower>();
  // Positive definite: GaussNewtonCovariance checked it.
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(h);
  const Matrix6d inverse = eigen.eigenvectors() * eigen.eigenvalues().cwiseInverse().asDiagonal() *
                           eigen.eigenvectors().transpose();
  out.covariance = inverse * meat * inverse;
  out.ok = out.covariance.allFinite();
  if (!out.ok) out.covariance = Matrix6d::Constant(kNaN);
  return out;
}

void PropagateFrameCovariance(const Eigen::Vector3d& p0, JawFrame* frame) {
  frame->path_point = PathPoint(frame->jaw, p0);
  if (!frame->upper.covariance_ok || !frame->lower.covariance_ok) {
    frame->stddev.fill(kNaN);
    frame->covariance = Matrix6d::Constant(kNaN);
    frame->path_point_stddev = Eigen::Vector3d::Constant(kNaN);
    return;
  }
  // J = U(θ_U) · L(θ_L)⁻¹: the outputs' Jacobian over both parts' twelve
  // parameters by central differences (smooth, and cheap next to a solve).
  const PartTheta upper(frame->upper), lower(frame->lower);
  auto outputs = [&](const std::array<double, 12>& delta) {
    return OutputsOf(upper.At(delta.data()) * lower.At(delta.data() + 6).Inverse(), p0);
  };
  Eigen::Matrix<double, 9, 12> a;
  for (int i = 0; i < 12; ++i) {
    const Eigen::Vector3d& centre = i < 6 ? upper.centre : lower.centre;
    const double h = (i % 6 < 3 ? 1.0 : 1.0 + centre.norm()) * 1e-6;
    std::array<double, 12> plus{}, minus{};
    plus[i] = h;
    minus[i] = -h;
    Outputs d = outputs(plus) - outputs(minus);
    for (int e = 0; e < 3; ++e) d[e] = std::remainder(d[e], 360.0);  // an Euler angle across ±180°
    a.col(i) = d / (2 * h);
  }
  Eigen::Matrix<double, 12, 12> parts = Eigen::Matrix<double, 12, 12>::Zero();
  parts.topLeftCorner<6, 6>() = frame->upper.covariance;
  parts.bottomRightCorner<6, 6>() = frame->lower.covariance;
  const Eigen::Matrix<double, 9, 9> c = a * parts * a.transpose();
  frame->covariance = c.topLeftCorner<6, 6>();
  for (int k = 0; k < 6; ++k) frame->stddev[k] = std::sqrt(std::max(0.0, c(k, k)));
  for (int k = 0; k < 3; ++k)
    frame->path_point_stddev[k] = std::sqrt(std::max(0.0, c(6 + k, 6 + k)));
}

Eigen::Vector3d LowestPoint(const Points& lower) {
  std::vector<std::array<double, 3>> lowest(std::min<std::size_t>(kPathLowestPoints, lower.size()));
  std::partial_sort_copy(lower.begin(), lower.end(), lowest.begin(), lowest.end(),
                         [](const auto& a, const auto& b) { return a[1] < b[1]; });
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : lowest) mean += Eigen::Vector3d(p[0], p[1], p[2]);
  return lowest.empty() ? mean : Eigen::Vector3d(mean / static_cast<double>(lowest.size()));
}

}  // namespace jaw_internal

std::string JawSummary::BriefReport() const {
  std::array<double, 3> lo{}, hi{}, path_lo{}, path_hi{};
  std::array<std::vector<double>, 6> sigma;
  for (int k = 0; k < 3; ++k) {
    lo[k] = hi[k] = frames.empty() ? 0.0 : frames[0].euler_deg[k];
    path_lo[k] = path_hi[k] = path_reference[k];
  }
  for (const JawFrame& f : frames) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], f.euler_deg[k]);
      hi[k] = std::max(hi[k], f.euler_deg[k]);
      path_lo[k] = std::min(path_lo[k], f.path_point[k]);
      path_hi[k] = std::max(path_hi[k], f.path_point[k]);
    }
    for (int k = 0; k < 6 && !f.is_reference; ++k) sigma[k].push_back(f.stddev[k]);
  }
  std::array<double, 6> median{};
  for (int k = 0; k < 6; ++k) {
    std::vector<double>& v = sigma[k];
    if (v.empty()) continue;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    median[k] = v[v.size() / 2];
  }
  std::size_t widest = 0;
  for (std::size_t k = 1; k < helical_axes.size(); ++k) {
    if (helical_axes[k].angle_deg > helical_axes[widest].angle_deg) widest = k;
  }
  char line[512];
  std::string text;
  std::snprintf(line, sizeof(line), "frames:     %zu (reference %d: %d upper, %d lower points)\n",
                frames.size(), reference, reference_upper_points, reference_lower_points);
  text += line;
  if (boundary_found) {
    std::snprintf(line, sizeof(line),
                  "boundary:   y %.4g (automatic: frame %d, %d of %d reference points moving, %d "
                  "misclassified); "
                  "margin %g\n",
                  boundary.y_level, search.frame, search.moving_points, search.points,
                  search.misclassified, boundary.margin);
  } else if (boundary.polygon.empty()) {
    std::snprintf(line, sizeof(line), "boundary:   y %.4g (given); margin %g\n", boundary.y_level,
                  boundary.margin);
  } else {
    std::snprintf(line, sizeof(line), "boundary:   polygon of %zu vertices (given); margin %g\n",
                  boundary.polygon.size(), boundary.margin);
  }
  text += line;
  std::snprintf(line, sizeof(line),
                "jaw angles: rx %.3f..%.3f  ry %.3f..%.3f  rz %.3f..%.3f deg\n"
                "stddev:     rx %.3g ry %.3g rz %.3g deg, tx %.3g ty %.3g tz %.3g units (median "
                "over the frames)\n",
                lo[0], hi[0], lo[1], hi[1], lo[2], hi[2], median[0], median[1], median[2],
                median[3], median[4], median[5]);
  text += line;
  std::snprintf(line, sizeof(line),
                "path:       point (%.4g, %.4g, %.4g) (%s); range x %.4g..%.4g  y %.4g..%.4g  z "
                "%.4g..%.4g units\n",
                path_reference[0], path_reference[1], path_reference[2],
                path_point_given ? "given" : "lowest lower-part point", path_lo[0], path_hi[0],
                path_lo[1], path_hi[1], path_lo[2], path_hi[2]);
  text += line;
  if (!helical_axes.empty()) {
    const HelicalAxis& h = helical_axes[widest];
    std::snprintf(line, sizeof(line),
                  "helical:    largest angle %.3f deg (frames %zu->%zu, slide %.3g units)\n",
                  h.angle_deg, widest, widest + 1, h.slide);
    text += line;
  }
  std::snprintf(line, sizeof(line),
                "failed:     %d frames\ntime:       %.3f s (%.3f s per frame)\n", failed_frames,
                seconds, frames.empty() ? 0.0 : seconds / static_cast<double>(frames.size()));
  return text + line;
}

}  // namespace surfreg

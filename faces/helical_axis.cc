#include "faces/helical_axis.h"

#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace surfreg {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

}  // namespace

const char* HelicalKindName(HelicalKind kind) {
  switch (kind) {
    case HelicalKind::kScrew:
      return "screw";
    case HelicalKind::kTranslation:
      return "translation";
    case HelicalKind::kNone:
      break;
  }
  return "none";
}

HelicalAxis FiniteHelicalAxis(const Eigen::Matrix4d& motion, const HelicalTolerance& tolerance) {
  const Eigen::Matrix3d r = motion.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = motion.topRightCorner<3, 1>();
  // Ceres' conversion stays accurate near 0 (the axis of a 0.1° turn) and
  // near π, where the trace formula loses the axis.
  Eigen::Vector3d w;
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(r.data()), w.data());
  const double angle = w.norm();
  HelicalAxis axis;
  if (!(angle >= tolerance.min_angle_rad)) {
    const double length = t.norm();
    if (!(length > tolerance.min_translation)) return axis;  // kNone: zeros
    axis.kind = HelicalKind::kTranslation;
    axis.direction = t / length;
    axis.point = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    axis.slide = length;
    return axis;
  }
  const Eigen::Vector3d n = w / angle;
  axis.kind = HelicalKind::kScrew;
  axis.direction = n;
  axis.angle_deg = std::min(angle * kDegrees, 180.0);
  axis.slide = n.dot(t);
  const Eigen::Vector3d across = t - axis.slide * n;
  // cot(θ/2) → 0 as θ → 180°: no loss of accuracy there.
  const double cot_half = 1.0 / std::tan(0.5 * angle);
  axis.point = 0.5 * (across + cot_half * n.cross(t));
  return axis;
}

HelicalAxis RelativeHelicalAxis(const Eigen::Matrix4d& pose_a, const Eigen::Matrix4d& pose_b,
                                const HelicalTolerance& tolerance) {
  // pose_a⁻¹ of a rigid pose: transpose and back-rotated shift (exact to rounding).
  Eigen::Matrix4d inverse_a = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d rt = pose_a.topLeftCorner<3, 3>().transpose();
  inverse_a.topLeftCorner<3, 3>() = rt;
  inverse_a.topRightCorner<3, 1>() = -(rt * pose_a.topRightCorner<3, 1>());
  HelicalTolerance scaled = tolerance;
  const double size =
      std::max(pose_a.topRightCorner<3, 1>().norm(), pose_b.topRightCorner<3, 1>().norm());
  scaled.min_translation = tolerance.min_translation * (1.0 + size);
  return FiniteHelicalAxis(pose_b * inverse_a, scaled);
}

Eigen::Vector3d PathPoint(const Eigen::Matrix4d& pose, const Eigen::Vector3d& p0) {
  return pose.topLeftCorner<3, 3>() * p0 + pose.topRightCorner<3, 1>();
}

}  // namespace surfreg

#include "registration/rigid_motion.h"

#include <cmath>

#include <ceres/rotation.h>

namespace surfreg {
namespace {

Eigen::Matrix3d Cross(const Eigen::Vector3d& w) {
  Eigen::Matrix3d k;
  k << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return k;
}

}  // namespace

Eigen::Matrix3d RotationMatrix(const std::array<double, 3>& rotation_vector) {
  Eigen::Matrix3d rotation;
  // Ceres handles the small-angle limit of the Rodrigues formula.
  ceres::AngleAxisToRotationMatrix(rotation_vector.data(),
                                   ceres::ColumnMajorAdapter3x3(rotation.data()));
  return rotation;
}

MotionDerivative DifferentiateMotion(const std::array<double, 3>& rotation_vector) {
  const Eigen::Vector3d w(rotation_vector.data());
  const double theta2 = w.squaredNorm();
  const double theta = std::sqrt(theta2);
  // J_r = I − a [ω]× + b [ω]×², a = (1 − cos θ)/θ², b = (θ − sin θ)/θ³.
  double a, b;
  if (theta < 1e-4) {  // series: the closed forms cancel catastrophically here
    a = 0.5 - theta2 / 24.0;
    b = 1.0 / 6.0 - theta2 / 120.0;
  } else {
    a = (1.0 - std::cos(theta)) / theta2;
    b = (theta - std::sin(theta)) / (theta2 * theta);
  }
  const Eigen::Matrix3d k = Cross(w);
  MotionDerivative result;
  result.rotation = RotationMatrix(rotation_vector);
  result.m = result.rotation * (Eigen::Matrix3d::Identity() - a * k + b * k * k);
  return result;
}

Eigen::Vector3d ApplyMotion(const RigidMotion& motion, const Eigen::Vector3d& p_in_moving) {
  const Eigen::Vector3d centre(motion.centre.data());
  const Eigen::Vector3d translation(motion.translation.data());
  return RotationMatrix(motion.rotation_vector) * (p_in_moving - centre) + centre + translation;
}

Eigen::Matrix4d ReferenceFromMoving(const RigidMotion& motion) {
  const Eigen::Matrix3d rotation = RotationMatrix(motion.rotation_vector);
  const Eigen::Vector3d centre(motion.centre.data());
  const Eigen::Vector3d translation(motion.translation.data());
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  matrix.topLeftCorner<3, 3>() = rotation;
  matrix.topRightCorner<3, 1>() = centre + translation - rotation * centre;
  return matrix;
}

Eigen::Vector4d MotionQuaternion(const RigidMotion& motion) {
  Eigen::Vector4d quaternion;
  ceres::AngleAxisToQuaternion(motion.rotation_vector.data(), quaternion.data());
  return quaternion;
}

}  // namespace surfreg

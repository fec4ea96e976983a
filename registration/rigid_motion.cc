#include "registration/rigid_motion.h"

#include <ceres/rotation.h>

namespace surfreg {
namespace {

Eigen::Matrix3d RotationMatrix(const RigidMotion& motion) {
  Eigen::Matrix3d rotation;
  // Ceres handles the small-angle limit of the Rodrigues formula.
  ceres::AngleAxisToRotationMatrix(motion.rotation_vector.data(),
                                   ceres::ColumnMajorAdapter3x3(rotation.data()));
  return rotation;
}

}  // namespace

Eigen::Vector3d ApplyMotion(const RigidMotion& motion, const Eigen::Vector3d& p_in_moving) {
  const Eigen::Vector3d centre(motion.centre.data());
  const Eigen::Vector3d translation(motion.translation.data());
  return RotationMatrix(motion) * (p_in_moving - centre) + centre + translation;
}

Eigen::Matrix4d ReferenceFromMoving(const RigidMotion& motion) {
  const Eigen::Matrix3d rotation = RotationMatrix(motion);
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

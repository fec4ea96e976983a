#include "registration/rigid_motion.h"

#include <cmath>

#include <Eigen/Geometry>
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

Rigid3d Rigid3d::FromMatrix(const Eigen::Matrix4d& matrix) {
  return {matrix.topLeftCorner<3, 3>(), matrix.topRightCorner<3, 1>()};
}

Rigid3d Rigid3d::RotationAbout(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& centre,
                               const Eigen::Vector3d& shift) {
  const Eigen::Matrix3d r = RotationMatrix({rotation_vector.x(), rotation_vector.y(), rotation_vector.z()});
  return {r, centre + shift - r * centre};
}

Eigen::Matrix4d Rigid3d::ToMatrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation;
  m.topRightCorner<3, 1>() = translation;
  return m;
}

Rigid3d Rigid3d::Inverse() const {
  const Eigen::Matrix3d rt = rotation.transpose();
  return {rt, -(rt * translation)};
}

Eigen::Vector3d Rigid3d::RotationVector() const {
  Eigen::Vector3d w;
  // Ceres' conversion is accurate near 0 and near π.
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(rotation.data()), w.data());
  return w;
}

bool IsRigid(const Eigen::Matrix4d& matrix, double tolerance) {
  if (!matrix.allFinite()) return false;
  const Eigen::Matrix3d r = matrix.topLeftCorner<3, 3>();
  if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= tolerance)) return false;
  if (!(std::fabs(r.determinant() - 1.0) <= tolerance)) return false;
  return (matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() <= tolerance;
}

Rigid3d RigidOfTheta(const std::array<double, 6>& theta, const Eigen::Vector3d& centre_local,
                     const std::array<double, 3>& origin) {
  const Eigen::Vector3d centre = centre_local + Eigen::Vector3d(origin[0], origin[1], origin[2]);
  return Rigid3d::RotationAbout({theta[0], theta[1], theta[2]}, centre, {theta[3], theta[4], theta[5]});
}

std::array<double, 6> ThetaOfRigid(const Rigid3d& reference_from_moving, const Eigen::Vector3d& centre_local,
                                   const std::array<double, 3>& origin) {
  const Eigen::Vector3d centre = centre_local + Eigen::Vector3d(origin[0], origin[1], origin[2]);
  const Eigen::Vector3d w = reference_from_moving.RotationVector();
  const Eigen::Vector3d t = reference_from_moving.ShiftOf(centre);
  return {w.x(), w.y(), w.z(), t.x(), t.y(), t.z()};
}

}  // namespace surfreg

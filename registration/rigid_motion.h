#pragma once
// The six registration parameters and the motion they define (DESIGN.md 4):
//
//   p_in_reference = R(ω) (p_in_moving − c) + c + t
//
// ω is a rotation vector (axis × angle, radians), t a translation (data
// units), c the moving surface's centroid. Rotating about c rather than the
// origin decouples rotation from translation and keeps the problem well
// conditioned for data far from the origin.
#include <array>

#include <Eigen/Core>

namespace surfreg {

struct RigidMotion {
  std::array<double, 3> rotation_vector = {0.0, 0.0, 0.0};  // ω, radians
  std::array<double, 3> translation = {0.0, 0.0, 0.0};      // t, data units
  std::array<double, 3> centre = {0.0, 0.0, 0.0};           // c, moving frame

  // Parameter block layout used by the Ceres costs: ω then t.
  static constexpr int kNumParameters = 6;
};

// p_in_reference for one moving point.
Eigen::Vector3d ApplyMotion(const RigidMotion& motion, const Eigen::Vector3d& p_in_moving);

// The same motion as a 4x4 homogeneous matrix (reference_from_moving).
Eigen::Matrix4d ReferenceFromMoving(const RigidMotion& motion);

// Unit quaternion (w, x, y, z) of R(ω).
Eigen::Vector4d MotionQuaternion(const RigidMotion& motion);

// R(ω) as a matrix.
Eigen::Matrix3d RotationMatrix(const std::array<double, 3>& rotation_vector);

// What the analytic Jacobians need: for q = R(ω)(p − c), the derivative of
// the moved point T(p) with respect to ω is −[q]× · M with M = R(ω)·J_r(ω)
// (J_r the right Jacobian of SO(3)); with respect to t it is the identity.
// So for any direction n, d(n·T(p))/dω = −Mᵀ (n × q). Series near ω = 0.
struct MotionDerivative {
  Eigen::Matrix3d rotation;  // R(ω)
  Eigen::Matrix3d m;         // R(ω) J_r(ω)
};
MotionDerivative DifferentiateMotion(const std::array<double, 3>& rotation_vector);

}  // namespace surfreg

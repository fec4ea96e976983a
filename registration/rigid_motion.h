#pragma once
// The six registration parameters and the motion they define (docs/method.md, How a registration runs):
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

// A rigid motion named for its frames (COLMAP's Rigid3d convention):
// `a_from_b` takes a point given in frame b to frame a,
//   p_a = rotation · p_b + translation.
// Align's answer is `reference_from_moving` in input coordinates (the
// moving file's points to the reference file's frame); its inverse is
// moving_from_reference, and a_from_b * b_from_c is a_from_c.
struct Rigid3d {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  // The top 3 × 4 of a homogeneous matrix (IsRigid says whether it is one).
  static Rigid3d FromMatrix(const Eigen::Matrix4d& matrix);
  // R(ω) about `centre`, then a shift: p ↦ R(ω)(p − centre) + centre + shift
  // (ω a rotation vector, radians).
  static Rigid3d RotationAbout(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& centre,
                               const Eigen::Vector3d& shift);
  Eigen::Matrix4d ToMatrix() const;
  Rigid3d Inverse() const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return rotation * p + translation; }
  Rigid3d operator*(const Rigid3d& b_from_c) const {
    return {rotation * b_from_c.rotation, rotation * b_from_c.translation + translation};
  }
  Eigen::Vector3d RotationVector() const;  // ω (radians), |ω| ≤ π
  // Where the motion takes `centre`, minus centre: RotationAbout's shift.
  Eigen::Vector3d ShiftOf(const Eigen::Vector3d& centre) const { return *this * centre - centre; }
};

// Whether `matrix` is rigid: the top-left 3 × 3 orthonormal with
// determinant +1 and the last row 0 0 0 1, each to `tolerance`.
bool IsRigid(const Eigen::Matrix4d& matrix, double tolerance = 1e-6);

// The registration's six parameters θ = (ω, t) about a centre given in the
// reference's local frame (input coordinates minus `origin`), as a motion
// in input coordinates, and back (the rotation vector of the inverse
// conversion has |ω| ≤ π).
Rigid3d RigidOfTheta(const std::array<double, 6>& theta, const Eigen::Vector3d& centre_local,
                     const std::array<double, 3>& origin);
std::array<double, 6> ThetaOfRigid(const Rigid3d& reference_from_moving, const Eigen::Vector3d& centre_local,
                                   const std::array<double, 3>& origin);

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

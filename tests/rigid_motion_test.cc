#include "registration/rigid_motion.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <ceres/jet.h>
#include <ceres/rotation.h>
#include <gtest/gtest.h>

namespace surfreg {
namespace {

// Independent construction with Eigen's AngleAxis, seeded random trials.
TEST(RigidMotionTest, MatchesEigenAngleAxisAboutCentre) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    RigidMotion motion;
    for (int k = 0; k < 3; ++k) {
      motion.rotation_vector[k] = 0.8 * u(rng);
      motion.translation[k] = 10.0 * u(rng);
      motion.centre[k] = 1e5 * u(rng);
    }
    const Eigen::Vector3d omega(motion.rotation_vector.data());
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized()).matrix();
    const Eigen::Vector3d centre(motion.centre.data()), t(motion.translation.data());
    const Eigen::Vector3d p = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1e5;
    const Eigen::Vector3d expected = rotation * (p - centre) + centre + t;
    EXPECT_LT((ApplyMotion(motion, p) - expected).norm(), 1e-9);
    const Eigen::Vector4d h = ReferenceFromMoving(motion) * p.homogeneous();
    EXPECT_LT((h.head<3>() - expected).norm(), 1e-8);
    EXPECT_DOUBLE_EQ(h[3], 1.0);
  }
}

TEST(RigidMotionTest, ZeroRotationIsPureTranslation) {
  RigidMotion motion;
  motion.translation = {1.0, -2.0, 3.0};
  motion.centre = {5.0, 6.0, 7.0};
  const Eigen::Matrix4d m = ReferenceFromMoving(motion);
  EXPECT_TRUE((m.topLeftCorner<3, 3>().isIdentity(0.0)));
  EXPECT_EQ(m(0, 3), 1.0);
  EXPECT_EQ(m(1, 3), -2.0);
  EXPECT_EQ(m(2, 3), 3.0);
}

TEST(RigidMotionTest, CentreIsMovedByTranslationOnly) {
  RigidMotion motion;
  motion.rotation_vector = {0.3, -0.2, 1.1};
  motion.translation = {0.5, 0.25, -4.0};
  motion.centre = {100.0, 200.0, 300.0};
  const Eigen::Vector3d moved = ApplyMotion(motion, Eigen::Vector3d(100.0, 200.0, 300.0));
  EXPECT_NEAR(moved.x(), 100.5, 1e-12);
  EXPECT_NEAR(moved.y(), 200.25, 1e-12);
  EXPECT_NEAR(moved.z(), 296.0, 1e-12);
}

TEST(RigidMotionTest, QuaternionOfHalfTurnAboutZ) {
  RigidMotion motion;
  motion.rotation_vector = {0.0, 0.0, M_PI};
  const Eigen::Vector4d q = MotionQuaternion(motion);
  EXPECT_NEAR(q[0], 0.0, 1e-15);
  EXPECT_NEAR(q[3], 1.0, 1e-15);
}

// d(R(ω) q)/dω by automatic differentiation through Ceres' own rotation code
// (an independent implementation) against −[Rq]× M. Ceres' own derivative is
// only accurate for angles well away from 0 (its small-angle branch is first
// order), so tiny angles are checked against long double central differences
// of Eigen's AngleAxis below.
TEST(RigidMotionTest, DerivativeMatchesAutomaticDifferentiation) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using Jet = ceres::Jet<double, 3>;
  for (double scale : {1e-2, 0.1, 1.0, 3.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      const std::array<double, 3> w = {scale * u(rng), scale * u(rng), scale * u(rng)};
      const Eigen::Vector3d p(u(rng), u(rng), u(rng));
      Jet wj[3], pj[3], out[3];
      for (int k = 0; k < 3; ++k) {
        wj[k] = Jet(w[k], k);
        pj[k] = Jet(p[k]);
      }
      ceres::AngleAxisRotatePoint(wj, pj, out);
      const MotionDerivative d = DifferentiateMotion(w);
      const Eigen::Vector3d q = d.rotation * p;
      for (int row = 0; row < 3; ++row) EXPECT_NEAR(q[row], out[row].a, 1e-14);
      // Column j of −[q]× M.
      Eigen::Matrix3d cross;
      cross << 0, -q.z(), q.y(), q.z(), 0, -q.x(), -q.y(), q.x(), 0;
      const Eigen::Matrix3d jacobian = -cross * d.m;
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) {
          EXPECT_NEAR(jacobian(row, col), out[row].v[col], 1e-12)
              << "scale " << scale << " row " << row << " col " << col;
        }
      }
    }
  }
}

TEST(RigidMotionTest, DerivativeNearZeroMatchesLongDoubleDifferences) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using Vector = Eigen::Matrix<long double, 3, 1>;
  auto rotate = [](const Vector& w, const Vector& p) -> Vector {
    const long double angle = w.norm();
    if (angle == 0) return p;
    return Eigen::AngleAxis<long double>(angle, w / angle) * p;
  };
  for (double scale : {0.0, 1e-12, 1e-9, 1e-6, 9e-5, 1.1e-4, 1e-3}) {
    for (int trial = 0; trial < 20; ++trial) {
      const std::array<double, 3> w = {scale * u(rng), scale * u(rng), scale * u(rng)};
      const Eigen::Vector3d p(u(rng), u(rng), u(rng));
      const MotionDerivative d = DifferentiateMotion(w);
      const Eigen::Vector3d q = d.rotation * p;
      Eigen::Matrix3d cross;
      cross << 0, -q.z(), q.y(), q.z(), 0, -q.x(), -q.y(), q.x(), 0;
      const Eigen::Matrix3d jacobian = -cross * d.m;
      const long double h = 1e-6L;
      for (int col = 0; col < 3; ++col) {
        Vector wp(w[0], w[1], w[2]), wm = wp;
        wp[col] += h;
        wm[col] -= h;
        const Vector pl(p.x(), p.y(), p.z());
        const Vector diff = (rotate(wp, pl) - rotate(wm, pl)) / (2 * h);
        for (int row = 0; row < 3; ++row) {
          EXPECT_NEAR(jacobian(row, col), static_cast<double>(diff[row]), 1e-11)
              << "scale " << scale << " row " << row << " col " << col;
        }
      }
    }
  }
}

}  // namespace
}  // namespace surfreg

namespace surfreg {
namespace {

Rigid3d RandomRigid(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  return {Eigen::AngleAxisd(3.0 * u(rng), axis).matrix(), Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1e3};
}

// Against the 4 × 4 matrices: composition is the matrix product, the
// inverse the matrix inverse, and applying one is the matrix times the
// homogeneous point; a_from_b * b_from_a is the identity.
TEST(Rigid3dTest, AgreesWithHomogeneousMatrices) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const Rigid3d a_from_b = RandomRigid(rng), b_from_c = RandomRigid(rng);
    const Eigen::Matrix4d ab = a_from_b.ToMatrix(), bc = b_from_c.ToMatrix();
    EXPECT_TRUE(IsRigid(ab));
    EXPECT_LT(((a_from_b * b_from_c).ToMatrix() - ab * bc).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((a_from_b.Inverse().ToMatrix() - ab.inverse()).cwiseAbs().maxCoeff(), 1e-9);
    const Rigid3d identity = a_from_b * a_from_b.Inverse();
    EXPECT_LT((identity.ToMatrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    const Eigen::Vector3d p(1e3, -250, 42);
    EXPECT_LT((a_from_b * p - (ab * p.homogeneous()).head<3>()).norm(), 1e-9);
    EXPECT_LT((Rigid3d::FromMatrix(ab).ToMatrix() - ab).cwiseAbs().maxCoeff(), 0.0 + 1e-15);
  }
}

// RotationAbout(ω, c, s) fixes the rotation and takes c to c + s; its
// rotation vector and ShiftOf(c) give ω and s back, for angles up to near π.
TEST(Rigid3dTest, RotationAboutACentreRoundTrips) {
  const Eigen::Vector3d centre(5e5, 4e6, 120);
  for (const double angle : {0.0, 1e-9, 0.02, 1.0, 3.1}) {
    const Eigen::Vector3d w = angle * Eigen::Vector3d(1, -2, 0.5).normalized();
    const Eigen::Vector3d shift(0.3, -7, 2);
    const Rigid3d motion = Rigid3d::RotationAbout(w, centre, shift);
    EXPECT_LT((motion * centre - (centre + shift)).norm(), 1e-8) << angle;
    EXPECT_LT((motion.RotationVector() - w).norm(), 1e-12) << angle;
    EXPECT_LT((motion.ShiftOf(centre) - shift).norm(), 1e-8) << angle;
    const Eigen::Matrix3d expected = angle > 0 ? Eigen::AngleAxisd(angle, w.normalized()).matrix()
                                               : Eigen::Matrix3d::Identity();
    EXPECT_LT((motion.rotation - expected).cwiseAbs().maxCoeff(), 1e-15 + 1e-15 * angle) << angle;
  }
}

// θ about a centre in a local frame with an origin: RigidOfTheta and
// ThetaOfRigid are inverse, and the motion does not depend on which centre
// θ is taken about.
TEST(Rigid3dTest, ThetaAboutAnyCentreIsTheSameMotion) {
  const std::array<double, 3> origin = {4.5e5, 5.2e6, 300};
  const Eigen::Vector3d centre(12, -30, 4), other(-800, 95, 60);
  const std::array<double, 6> theta = {0.01, -0.03, 0.2, 1.5, -2.5, 0.25};
  const Rigid3d motion = RigidOfTheta(theta, centre, origin);
  const std::array<double, 6> back = ThetaOfRigid(motion, centre, origin);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(back[k], theta[k], 1e-9) << k;
  const Rigid3d again = RigidOfTheta(ThetaOfRigid(motion, other, origin), other, origin);
  EXPECT_LT((again.ToMatrix() - motion.ToMatrix()).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Rigid3dTest, IsRigidRejectsScaleShearAndReflection) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  EXPECT_TRUE(IsRigid(m));
  m(0, 0) = 1.01;  // scale
  EXPECT_FALSE(IsRigid(m));
  m = Eigen::Matrix4d::Identity();
  m(0, 1) = 0.1;  // shear
  EXPECT_FALSE(IsRigid(m));
  m = Eigen::Matrix4d::Identity();
  m(2, 2) = -1;  // a reflection is orthonormal but not a rotation
  EXPECT_FALSE(IsRigid(m));
  m = Eigen::Matrix4d::Identity();
  m(3, 0) = 0.5;  // a projective row
  EXPECT_FALSE(IsRigid(m));
  m = Eigen::Matrix4d::Identity();
  m(1, 3) = std::nan("");
  EXPECT_FALSE(IsRigid(m));
}

}  // namespace
}  // namespace surfreg

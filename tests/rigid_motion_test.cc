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

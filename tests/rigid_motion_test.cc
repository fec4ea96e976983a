#include "registration/rigid_motion.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
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

}  // namespace
}  // namespace surfreg

// The finite helical axis (faces/helical_axis.h): known screws applied to
// known poses recovered, the degenerate motions, the path of a point.
#include "faces/helical_axis.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The screw x ↦ R(x − c) + c + s n, R the rotation by angle_deg about n.
Eigen::Matrix4d Screw(const Eigen::Vector3d& n, const Eigen::Vector3d& c, double angle_deg,
                      double slide) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle_deg * kPi / 180, n).toRotationMatrix();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = c - r * c + slide * n;
  return m;
}

Eigen::Vector3d RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

Eigen::Matrix4d RandomPose(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(0, 40), shift(-20, 20);
  return Screw(RandomUnit(rng), Eigen::Vector3d(shift(rng), shift(rng), shift(rng)), angle(rng),
               shift(rng));
}

TEST(HelicalAxis, RecoversKnownScrewsBetweenPoses) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> coordinate(-100, 100), slide(-5, 5);
  const double angles[] = {0.1, 0.5, 3, 8, 30, 90, 150, 170, 179};
  int cases = 0;
  for (double angle : angles) {
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Vector3d n = RandomUnit(rng);
      const Eigen::Vector3d c(coordinate(rng), coordinate(rng), coordinate(rng));
      const double s = slide(rng);
      const Eigen::Matrix4d pose_a = RandomPose(rng);
      const Eigen::Matrix4d pose_b = Screw(n, c, angle, s) * pose_a;
      const HelicalAxis axis = RelativeHelicalAxis(pose_a, pose_b);
      ASSERT_EQ(axis.kind, HelicalKind::kScrew) << angle;
      const Eigen::Vector3d closest = c - c.dot(n) * n;  // the axis' point closest to the origin
      EXPECT_LT((axis.direction - n).norm(), 1e-6) << angle;
      EXPECT_NEAR(axis.direction.norm(), 1.0, 1e-12);
      EXPECT_LT((axis.point - closest).norm(), 1e-6) << angle << " " << axis.point.transpose();
      EXPECT_NEAR(axis.point.dot(axis.direction), 0.0, 1e-6);
      EXPECT_NEAR(axis.angle_deg, angle, 1e-6);
      EXPECT_NEAR(axis.slide, s, 1e-6) << angle;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 45);
}

// A negative angle about n is the positive one about −n: the sign rule.
TEST(HelicalAxis, AngleIsNonNegativeAboutTheReturnedDirection) {
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, -2).normalized();
  const Eigen::Vector3d c(3, -4, 5);
  const HelicalAxis axis = FiniteHelicalAxis(Screw(n, c, -25, 1.5));
  EXPECT_NEAR(axis.angle_deg, 25, 1e-9);
  EXPECT_LT((axis.direction + n).norm(), 1e-12);
  EXPECT_NEAR(axis.slide, -1.5, 1e-12);  // the same slide along −n
  EXPECT_LT((axis.point - (c - c.dot(n) * n)).norm(), 1e-9);
}

// A half turn: the axis direction is defined up to its sign; either way the
// screw rebuilt from the answer is the motion.
TEST(HelicalAxis, HalfTurnRebuildsTheMotion) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Matrix4d motion = Screw(n, Eigen::Vector3d(7, 1, -2), 180, 0.75);
  const HelicalAxis axis = FiniteHelicalAxis(motion);
  ASSERT_EQ(axis.kind, HelicalKind::kScrew);
  EXPECT_NEAR(axis.angle_deg, 180, 1e-9);
  EXPECT_NEAR(std::fabs(axis.direction.dot(n)), 1.0, 1e-9);
  EXPECT_LT((Screw(axis.direction, axis.point, axis.angle_deg, axis.slide) - motion).norm(), 1e-9);
}

TEST(HelicalAxis, PureTranslation) {
  std::mt19937_64 rng(5);
  const Eigen::Matrix4d pose_a = RandomPose(rng);
  Eigen::Matrix4d shift = Eigen::Matrix4d::Identity();
  shift.topRightCorner<3, 1>() = Eigen::Vector3d(0.3, -1.2, 0.4);
  const HelicalAxis axis = RelativeHelicalAxis(pose_a, shift * pose_a);
  EXPECT_EQ(axis.kind, HelicalKind::kTranslation);
  EXPECT_STREQ(HelicalKindName(axis.kind), "translation");
  EXPECT_LT((axis.direction - Eigen::Vector3d(0.3, -1.2, 0.4).normalized()).norm(), 1e-12);
  EXPECT_NEAR(axis.slide, Eigen::Vector3d(0.3, -1.2, 0.4).norm(), 1e-12);
  EXPECT_EQ(axis.angle_deg, 0.0);
  EXPECT_TRUE(std::isnan(axis.point.x()) && std::isnan(axis.point.y()) &&
              std::isnan(axis.point.z()));
}

TEST(HelicalAxis, IdentityIsNoMotion) {
  std::mt19937_64 rng(9);
  const Eigen::Matrix4d pose = RandomPose(rng);
  for (const HelicalAxis& axis :
       {FiniteHelicalAxis(Eigen::Matrix4d::Identity()), RelativeHelicalAxis(pose, pose)}) {
    EXPECT_EQ(axis.kind, HelicalKind::kNone);
    EXPECT_EQ(axis.direction, Eigen::Vector3d::Zero());
    EXPECT_EQ(axis.point, Eigen::Vector3d::Zero());
    EXPECT_EQ(axis.angle_deg, 0.0);
    EXPECT_EQ(axis.slide, 0.0);
  }
}

TEST(HelicalAxis, PathPointIsThePoseApplied) {
  const Eigen::Matrix4d pose = Screw(Eigen::Vector3d::UnitX(), Eigen::Vector3d(0, 10, -90), 90, 0);
  // A quarter turn about the x axis through (0, 10, −90): (0, 10, −80) → (0, 0, −90).
  EXPECT_LT((PathPoint(pose, Eigen::Vector3d(0, 10, -80)) - Eigen::Vector3d(0, 0, -90)).norm(),
            1e-12);
  EXPECT_EQ(PathPoint(Eigen::Matrix4d::Identity(), Eigen::Vector3d(1, 2, 3)),
            Eigen::Vector3d(1, 2, 3));
}

}  // namespace
}  // namespace surfreg

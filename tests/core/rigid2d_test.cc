#include "shared/core/rigid2d.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

TEST(NormalizeAngleTest, WrapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(NormalizeAngle(0.0), 0.0);
  EXPECT_NEAR(NormalizeAngle(3 * M_PI / 2), -M_PI / 2, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-3 * M_PI / 2), M_PI / 2, 1e-12);
  EXPECT_NEAR(NormalizeAngle(M_PI), -M_PI, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-M_PI), -M_PI, 1e-12);
  EXPECT_NEAR(NormalizeAngle(101 * M_PI + 0.25), -M_PI + 0.25, 1e-9);
  for (double a = -50.0; a < 50.0; a += 0.37) {
    const double n = NormalizeAngle(a);
    EXPECT_GE(n, -M_PI);
    EXPECT_LT(n, M_PI);
    EXPECT_NEAR(std::cos(n), std::cos(a), 1e-9);
    EXPECT_NEAR(std::sin(n), std::sin(a), 1e-9);
  }
}

TEST(Rigid2dTest, AppliesRotationThenTranslation) {
  const Rigid2d robot_in_map(1.0, 2.0, M_PI / 2);
  const Eigen::Vector2d p = robot_in_map * Eigen::Vector2d(1.0, 0.0);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 3.0, 1e-12);
  const Eigen::Vector2f pf = robot_in_map * Eigen::Vector2f(0.0f, 1.0f);
  EXPECT_NEAR(pf.x(), 0.0f, 1e-6f);
  EXPECT_NEAR(pf.y(), 2.0f, 1e-6f);
}

TEST(Rigid2dTest, ComposeMatchesSequentialApplication) {
  const Rigid2d a(0.5, -1.0, 0.3), b(2.0, 0.7, -1.2);
  const Eigen::Vector2d p(0.3, 0.9);
  const Eigen::Vector2d composed = (a * b) * p;
  const Eigen::Vector2d sequential = a * (b * p);
  EXPECT_NEAR((composed - sequential).norm(), 0.0, 1e-12);
  EXPECT_NEAR((a * b).rotation(), NormalizeAngle(0.3 - 1.2), 1e-12);
}

TEST(Rigid2dTest, InverseUndoes) {
  const Rigid2d t(3.0, -4.0, 2.5);
  EXPECT_THAT(t * t.inverse(), IsNearPose(Rigid2d::Identity(), 1e-12, 1e-12));
  EXPECT_THAT(t.inverse() * t, IsNearPose(Rigid2d::Identity(), 1e-12, 1e-12));
  const Eigen::Vector2d p(1.0, 1.0);
  EXPECT_NEAR((t.inverse() * (t * p) - p).norm(), 0.0, 1e-12);
}

TEST(Rigid2dTest, RotationIsAlwaysNormalised) {
  EXPECT_NEAR(Rigid2d(0, 0, 7.0).rotation(), 7.0 - 2 * M_PI, 1e-12);
  EXPECT_NEAR((Rigid2d(0, 0, 3.0) * Rigid2d(0, 0, 3.0)).rotation(), 6.0 - 2 * M_PI, 1e-12);
}

TEST(Rigid2dTest, InterpolateTakesShortestArc) {
  const Rigid2d a(0.0, 0.0, M_PI - 0.1), b(2.0, 4.0, -M_PI + 0.1);
  const Rigid2d mid = Interpolate(a, b, 0.5);
  EXPECT_NEAR(mid.x(), 1.0, 1e-12);
  EXPECT_NEAR(mid.y(), 2.0, 1e-12);
  EXPECT_NEAR(std::abs(mid.rotation()), M_PI, 1e-9);
  EXPECT_THAT(Interpolate(a, b, 0.0), IsNearPose(a, 1e-12, 1e-12));
  EXPECT_THAT(Interpolate(a, b, 1.0), IsNearPose(b, 1e-12, 1e-12));
}

TEST(Rigid2dTest, NonFiniteIsDetected) {
  EXPECT_TRUE(Rigid2d(1, 2, 3).IsFinite());
  EXPECT_FALSE(Rigid2d(std::nan(""), 0, 0).IsFinite());
  EXPECT_FALSE(Rigid2d(0, 0, INFINITY).IsFinite());
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/detection/relative_heading.h"

#include <gtest/gtest.h>

#include "shared/core/rigid2d.h"

namespace fleetmap {
namespace {

RobotDetection Seen(const std::string& observer, const std::string& observed,
                    const Eigen::Vector2d& position, double time) {
  RobotDetection d;
  d.observer_id = observer;
  d.observed_id = observed;
  d.position_in_observer = position;
  d.covariance = 1e-4 * Eigen::Matrix2d::Identity();
  d.timestamp = time;
  return d;
}

TEST(RelativeHeadingTest, MutualDetectionsGiveHeading) {
  for (double heading : {-3.0, -1.0, 0.0, 0.5, 2.5}) {
    const Rigid2d a_in_world(1.0, 2.0, 0.3);
    const Rigid2d b_in_world = a_in_world * Rigid2d(3.0, 1.0, heading);
    const Eigen::Vector2d b_in_a = a_in_world.inverse() * b_in_world.translation();
    const Eigen::Vector2d a_in_b = b_in_world.inverse() * a_in_world.translation();
    const auto result = MutualRelativeHeading(Seen("a", "b", b_in_a, 10.0),
                                              Seen("b", "a", a_in_b, 10.01));
    ASSERT_TRUE(result);
    EXPECT_NEAR(NormalizeAngle(result->heading - heading), 0.0, 1e-9);
    EXPECT_GT(result->variance, 0.0);
    EXPECT_LT(result->variance, 1e-4);
  }
}

TEST(RelativeHeadingTest, RejectsNonPairs) {
  const auto ab = Seen("a", "b", {2.0, 0.0}, 1.0);
  EXPECT_FALSE(MutualRelativeHeading(ab, Seen("b", "c", {2.0, 0.0}, 1.0)));
  EXPECT_FALSE(MutualRelativeHeading(ab, Seen("b", "a", {2.0, 0.0}, 2.0)));
  EXPECT_FALSE(MutualRelativeHeading(ab, Seen("b", "a", {0.0, 0.0}, 1.0)));
}

}  // namespace
}  // namespace fleetmap

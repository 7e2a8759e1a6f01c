#include "robot_agent/slam/odometry_buffer.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

TEST(OdometryBufferTest, InterpolatesAndHoldsAtTheEnds) {
  OdometryBuffer buffer;
  EXPECT_FALSE(buffer.PoseAt(0.0).has_value());
  std::string error;
  ASSERT_TRUE(buffer.Add({1.0, Rigid2d(0.0, 0.0, 0.0)}, &error));
  ASSERT_TRUE(buffer.Add({2.0, Rigid2d(1.0, 2.0, 0.4)}, &error));
  EXPECT_THAT(*buffer.PoseAt(0.5), IsNearPose(Rigid2d(0.0, 0.0, 0.0), 1e-9, 1e-9));
  EXPECT_THAT(*buffer.PoseAt(1.5), IsNearPose(Rigid2d(0.5, 1.0, 0.2), 1e-9, 1e-9));
  EXPECT_THAT(*buffer.PoseAt(3.0), IsNearPose(Rigid2d(1.0, 2.0, 0.4), 1e-9, 1e-9));
}

TEST(OdometryBufferTest, RejectsTimeGoingBackwardsAndNonFiniteReadings) {
  OdometryBuffer buffer;
  std::string error;
  ASSERT_TRUE(buffer.Add({5.0, Rigid2d()}, &error));
  EXPECT_FALSE(buffer.Add({4.0, Rigid2d()}, &error));
  EXPECT_NE(error.find("backwards"), std::string::npos) << error;
  EXPECT_FALSE(buffer.Add({6.0, Rigid2d(NAN, 0.0, 0.0)}, &error));
  EXPECT_THAT(*buffer.PoseAt(5.0), IsNearPose(Rigid2d(), 1e-12, 1e-12));
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/detection/laser_body.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::AddCylinder;
using testing::SegmentWorld;

constexpr double kBody = 0.2;  // the robots' body radius

// Two robots in a room, one ahead and one beside us (outside a forward camera's view): both
// are found where they stand, and the room's walls and corners are not bodies.
TEST(LaserBodyTest, FindsTheRobotsInARoomAndNothingElse) {
  SegmentWorld world = testing::BoxWorld({-1.0, -5.0}, {10.0, 5.0});
  const Eigen::Vector2d ahead(3.0, 0.5), beside(0.3, -2.0);
  AddCylinder(ahead, kBody, &world);
  AddCylinder(beside, kBody, &world);
  const Rigid2d sensor_in_robot(0.1, 0.0, 0.0);
  const LaserScan scan = testing::SimulateScan(world, Rigid2d(), 181, -M_PI / 2, M_PI / 180, 8.0f,
                                               sensor_in_robot);
  const std::vector<Eigen::Vector2d> bodies = FindLaserBodies(scan, kBody);
  ASSERT_EQ(bodies.size(), 2u);
  const bool ahead_first = (bodies[0] - ahead).norm() < (bodies[1] - ahead).norm();
  EXPECT_LT((bodies[ahead_first ? 0 : 1] - ahead).norm(), 0.01);   // robot frame, mount applied
  EXPECT_LT((bodies[ahead_first ? 1 : 0] - beside).norm(), 0.01);
}

// Free-standing things that are not robots: a square box seen corner-on, the end of a thick
// wall seen with a piece of its side, a thin post and a pillar much wider than a robot.
TEST(LaserBodyTest, IgnoresCornersWallEndsPostsAndWidePillars) {
  SegmentWorld world = testing::BoxWorld({-1.0, -6.0}, {12.0, 6.0});
  // A 0.3 m box turned 45 degrees, 2 m ahead: its near corner points at us.
  const Eigen::Vector2d box(2.0, 0.0);
  const double h = 0.15 * std::sqrt(2.0);
  const Eigen::Vector2d corners[4] = {box + Eigen::Vector2d(-h, 0), box + Eigen::Vector2d(0, h),
                                      box + Eigen::Vector2d(h, 0), box + Eigen::Vector2d(0, -h)};
  for (int i = 0; i < 4; ++i) world.push_back({corners[i], corners[(i + 1) % 4]});
  // A 0.2 m thick wall from the side wall at y = 6 down to y = 1.5, at x = 2.5..2.7.
  testing::AddBox({2.5, 1.5}, {2.7, 6.0}, &world);
  AddCylinder({3.0, -2.0}, 0.03, &world);  // a post
  AddCylinder({5.0, -3.5}, 0.6, &world);   // a pillar
  const LaserScan scan = testing::SimulateScan(world, Rigid2d());
  for (const Eigen::Vector2d& body : FindLaserBodies(scan, kBody)) ADD_FAILURE() << "a body at " << body.transpose();
}

// Without a camera, a body needs min_returns returns (fewer fit the end of a thick wall as
// well): a robot 6 m away shows only 4 or 5 at one-degree beams.
TEST(LaserBodyTest, AFarRobotWithFewReturnsIsFoundOnlyWhenAllowed) {
  SegmentWorld world = testing::BoxWorld({-1.0, -5.0}, {10.0, 5.0});
  const Eigen::Vector2d far(6.0, 0.3);
  AddCylinder(far, kBody, &world);
  const LaserScan scan = testing::SimulateScan(world, Rigid2d());
  EXPECT_TRUE(FindLaserBodies(scan, kBody).empty());
  LaserBodyOptions few;
  few.min_returns = 3;
  const std::vector<Eigen::Vector2d> bodies = FindLaserBodies(scan, kBody, few);
  ASSERT_EQ(bodies.size(), 1u);
  EXPECT_LT((bodies[0] - far).norm(), 0.01);
}

// A robot standing against a wall does not stand out of it, and a scan with nothing usable
// in it yields nothing (no crash on an empty scan or a zero beam spacing).
TEST(LaserBodyTest, NothingFromBodiesAgainstWallsOrFromBadScans) {
  SegmentWorld world = testing::BoxWorld({-1.0, -5.0}, {10.0, 5.0});
  AddCylinder({3.0, -4.8}, kBody, &world);  // touching the wall at y = -5
  EXPECT_TRUE(FindLaserBodies(testing::SimulateScan(world, Rigid2d()), kBody).empty());
  EXPECT_TRUE(FindLaserBodies(LaserScan(), kBody).empty());
  LaserScan flat = testing::SimulateScan(world, Rigid2d());
  flat.angle_increment = 0.0f;
  EXPECT_TRUE(FindLaserBodies(flat, kBody).empty());
}

}  // namespace
}  // namespace fleetmap

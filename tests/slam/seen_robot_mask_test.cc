#include "robot_agent/slam/seen_robot_mask.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// A corridor (walls at y = +-1) with another robot (a 0.2 m disk) standing 3 m ahead of where
// we were when the camera saw it.
struct Scene {
  testing::SegmentWorld world = {{Eigen::Vector2d(-5, -1), Eigen::Vector2d(20, -1)},
                                 {Eigen::Vector2d(-5, 1), Eigen::Vector2d(20, 1)}};
  Eigen::Vector2d other{3.0, 0.0};
  Scene() {
    // The other robot's body as a square of four short walls.
    testing::AddBox(other - Eigen::Vector2d(0.2, 0.2), other + Eigen::Vector2d(0.2, 0.2), &world);
  }
};

RobotDetection SeenAt(double time, const Eigen::Vector2d& in_observer) {
  RobotDetection d;
  d.observer_id = "me";
  d.observed_id = "other";
  d.timestamp = time;
  d.position_in_observer = in_observer;
  d.covariance = Eigen::Matrix2d::Identity() * 1e-4;
  return d;
}

// Returns of `scan` ending within `radius` of `center` (sensor frame).
int CountNear(const LaserScan& scan, const Eigen::Vector2d& center, double radius) {
  int n = 0;
  for (int i = 0; i < scan.size(); ++i) {
    if (!scan.IsReturn(i)) continue;
    const double r = scan.ranges[static_cast<size_t>(i)];
    n += (Eigen::Vector2d(r * std::cos(scan.angle(i)), r * std::sin(scan.angle(i))) - center).norm() < radius;
  }
  return n;
}

// Seen at t = 0 from x = 0; we drive 1 m on by odometry: the scan at t = 0.2 loses exactly the
// returns off the robot (now 2 m ahead in our frame), and keeps the corridor's walls.
TEST(SeenRobotMaskTest, MasksTheSeenRobotCarriedByOdometry) {
  const Scene scene;
  SeenRobotMask mask;
  mask.AddOdometry(0.0, Rigid2d());
  mask.AddOdometry(0.2, Rigid2d(1.0, 0.0, 0.0));
  mask.AddDetection(SeenAt(0.0, scene.other));
  LaserScan scan = testing::SimulateScan(scene.world, Rigid2d(1.0, 0.0, 0.0));
  scan.timestamp = 0.2;
  const LaserScan original = scan;
  const int on_robot = CountNear(original, Eigen::Vector2d(2.0, 0.0), 0.3);
  ASSERT_GT(on_robot, 5);
  const int returns = original.CountReturns();
  const int masked = mask.Apply(&scan);
  EXPECT_EQ(masked, on_robot);
  EXPECT_EQ(scan.CountReturns(), returns - masked);
  EXPECT_EQ(CountNear(scan, Eigen::Vector2d(2.0, 0.0), 0.3), 0);
  // The walls beside the robot are more than its reach (0.35 m + 1 m/s * 0.2 s) away: kept.
  for (int i = 0; i < scan.size(); ++i) {
    if (!original.IsReturn(i)) continue;
    const double r = original.ranges[static_cast<size_t>(i)];
    const Eigen::Vector2d end(r * std::cos(scan.angle(i)), r * std::sin(scan.angle(i)));
    if ((end - Eigen::Vector2d(2.0, 0.0)).norm() > 0.56) {
      EXPECT_TRUE(scan.IsReturn(i)) << "beam " << i;
    }
  }
}

// Odometry at 0.06 s steps and scans at 0.1 s (as in the simulator): a scan usually arrives
// before the reading that covers its time. It is still masked, from the latest reading.
TEST(SeenRobotMaskTest, MasksAScanNewerThanTheLatestOdometry) {
  const Scene scene;
  SeenRobotMask mask;
  mask.AddOdometry(0.0, Rigid2d());
  mask.AddOdometry(0.06, Rigid2d(0.03, 0.0, 0.0));
  mask.AddDetection(SeenAt(0.0, scene.other));
  LaserScan scan = testing::SimulateScan(scene.world, Rigid2d(0.05, 0.0, 0.0));
  scan.timestamp = 0.1;
  const int on_robot = CountNear(scan, Eigen::Vector2d(2.95, 0.0), 0.3);
  ASSERT_GT(on_robot, 5);
  EXPECT_GE(mask.Apply(&scan), on_robot);
  EXPECT_EQ(CountNear(scan, Eigen::Vector2d(2.95, 0.0), 0.3), 0);
}

// Nothing is masked for a detection older than max_age, one made after the scan, or a scan
// outside the odometry we have.
TEST(SeenRobotMaskTest, MasksOnlyWithFreshDetectionsAndOdometry) {
  const Scene scene;
  LaserScan scan = testing::SimulateScan(scene.world, Rigid2d());
  SeenRobotMaskOptions options;
  options.max_age = 1.0;
  {
    SeenRobotMask mask(options);
    mask.AddOdometry(0.0, Rigid2d());
    mask.AddOdometry(2.0, Rigid2d());
    mask.AddDetection(SeenAt(0.0, scene.other));
    scan.timestamp = 1.5;
    EXPECT_EQ(mask.Apply(&scan), 0);  // too old
    scan.timestamp = 0.5;
    EXPECT_GT(mask.Apply(&scan), 0);
  }
  {
    SeenRobotMask mask(options);
    mask.AddOdometry(0.0, Rigid2d());
    mask.AddOdometry(2.0, Rigid2d());
    mask.AddDetection(SeenAt(1.0, scene.other));
    LaserScan before = testing::SimulateScan(scene.world, Rigid2d());
    before.timestamp = 0.5;
    EXPECT_EQ(mask.Apply(&before), 0);  // seen after the scan
    LaserScan later = testing::SimulateScan(scene.world, Rigid2d());
    later.timestamp = 2.5;
    EXPECT_EQ(mask.Apply(&later), 0);  // no odometry within max_odometry_gap of the scan
  }
}

// A body the laser alone found masks the scans of the next max_laser_body_age seconds (carried
// by odometry like a detection), and is then forgotten.
TEST(SeenRobotMaskTest, MasksLaserBodiesForAShortWhile) {
  const Scene scene;
  SeenRobotMaskOptions options;
  options.max_laser_body_age = 0.3;
  options.laser_bodies_must_move = false;  // one sighting is enough here
  SeenRobotMask mask(options);
  EXPECT_TRUE(mask.empty());
  mask.AddOdometry(0.0, Rigid2d());
  mask.AddOdometry(1.0, Rigid2d(1.0, 0.0, 0.0));
  mask.AddLaserBodies(0.0, {scene.other});
  EXPECT_FALSE(mask.empty());
  LaserScan scan = testing::SimulateScan(scene.world, Rigid2d(0.2, 0.0, 0.0));
  scan.timestamp = 0.2;
  const int on_robot = CountNear(scan, Eigen::Vector2d(2.8, 0.0), 0.3);
  ASSERT_GT(on_robot, 5);
  EXPECT_EQ(mask.Apply(&scan), on_robot);
  EXPECT_EQ(CountNear(scan, Eigen::Vector2d(2.8, 0.0), 0.3), 0);

  LaserScan later = testing::SimulateScan(scene.world, Rigid2d(0.5, 0.0, 0.0));
  later.timestamp = 0.5;
  EXPECT_EQ(mask.Apply(&later), 0);  // older than max_laser_body_age
  mask.AddLaserBodies(0.9, {});      // the window moves on: the old body is dropped
  EXPECT_TRUE(mask.empty());
}

// By default a body the laser finds masks only once it is found again somewhere else: one on
// the same spot scan after scan (a pillar) never masks; one that moves 5 cm per 0.1 s (0.5 m/s)
// masks from its second sighting. We drive 0.1 m per scan, so the odometry frame matters.
TEST(SeenRobotMaskTest, MasksOnlyLaserBodiesThatMove) {
  const Scene scene;
  for (const bool moving : {false, true}) {
    SeenRobotMask mask;
    int masking = 0;
    for (int k = 0; k < 5; ++k) {
      const double t = 0.1 * k;
      const Rigid2d me(0.1 * k, 0.0, 0.0);
      mask.AddOdometry(t, me);
      // The body in the world, seen from where we are.
      const Eigen::Vector2d body = scene.other + Eigen::Vector2d(moving ? 0.05 * k : 0.0, 0.0);
      mask.AddLaserBodies(t, {me.inverse() * body});
      LaserScan scan = testing::SimulateScan(scene.world, me);
      scan.timestamp = t;
      masking += mask.Apply(&scan) > 0;
    }
    EXPECT_EQ(masking, moving ? 4 : 0) << (moving ? "moving" : "fixed");
  }
}

}  // namespace
}  // namespace fleetmap

#include "shared/core/laser_scan.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(LaserScanTest, NoReturnReadingsStayDistinct) {
  const LaserScan scan = MakeLaserScan(1.0, -1.0f, 1.0f, 0.1f, 10.0f,
                                       {1.0f, 10.0f, 0.05f, NAN, 81.9f, 2.0f, -1.0f, INFINITY});
  ASSERT_EQ(scan.size(), 8);
  EXPECT_TRUE(scan.IsReturn(0));
  EXPECT_FALSE(scan.IsReturn(1));  // at max range
  EXPECT_FALSE(scan.IsReturn(2));  // below min range
  EXPECT_FALSE(scan.IsReturn(3));  // NaN
  EXPECT_FALSE(scan.IsReturn(4));  // beyond max range
  EXPECT_TRUE(scan.IsReturn(5));
  EXPECT_FALSE(scan.IsReturn(6));  // negative
  EXPECT_FALSE(scan.IsReturn(7));
  EXPECT_EQ(scan.CountReturns(), 2);
  EXPECT_EQ(ToPointsInSensorFrame(scan).size(), 2u);
}

TEST(LaserScanTest, PointsInSensorAndRobotFrames) {
  const Rigid2d mount(0.2, 0.0, M_PI);  // laser 20 cm ahead, looking backwards
  const LaserScan scan = MakeLaserScan(0.0, 0.0f, static_cast<float>(M_PI / 2), 0.0f, 30.0f,
                                       {1.0f, 2.0f}, mount);
  const auto sensor = ToPointsInSensorFrame(scan);
  ASSERT_EQ(sensor.size(), 2u);
  EXPECT_NEAR(sensor[0].x(), 1.0f, 1e-6f);
  EXPECT_NEAR(sensor[0].y(), 0.0f, 1e-6f);
  EXPECT_NEAR(sensor[1].x(), 0.0f, 1e-6f);
  EXPECT_NEAR(sensor[1].y(), 2.0f, 1e-6f);
  const auto robot = ToPointsInRobotFrame(scan);
  EXPECT_NEAR(robot[0].x(), -0.8f, 1e-6f);
  EXPECT_NEAR(robot[0].y(), 0.0f, 1e-6f);
  EXPECT_NEAR(robot[1].x(), 0.2f, 1e-6f);
  EXPECT_NEAR(robot[1].y(), -2.0f, 1e-6f);
}

TEST(LaserScanTest, HorizonIsTheNearerOfTheSensorsLimitAndTheCap) {
  LaserScan scan;
  scan.range_max = 8.0f;
  EXPECT_FLOAT_EQ(Horizon(scan, 20.0f), 8.0f);
  EXPECT_FLOAT_EQ(Horizon(scan, 5.0f), 5.0f);
  scan.range_max = 0.0f;  // unset
  EXPECT_FLOAT_EQ(Horizon(scan, 20.0f), 20.0f);
}

// Beams at 0, 90, 180 degrees; the sensor sees 10 m, the user caps at 6 m.
TEST(LaserScanTest, ReturnsInsideTheHorizonAndEndsOfBeamsThatSawNothing) {
  const LaserScan scan = MakeLaserScan(0.0, 0.0f, static_cast<float>(M_PI / 2), 0.0f, 10.0f,
                                       {2.0f, 5.5f, NAN});
  // Horizon 6 m, margin 1 m: only the 2 m return is matched.
  const auto inside = ReturnsInsideHorizon(scan, 6.0f, 1.0f);
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_NEAR(inside[0].x(), 2.0f, 1e-6f);
  // The NaN beam saw nothing: it ends at the 6 m horizon, straight behind. Both returns lie
  // within the horizon, so they end nowhere.
  const auto ends = NoReturnEnds(scan, 6.0f);
  ASSERT_EQ(ends.size(), 1u);
  EXPECT_NEAR(ends[0].x(), -6.0f, 1e-5f);
  EXPECT_NEAR(ends[0].y(), 0.0f, 1e-5f);
  // Capped at 4 m, the 5.5 m return lies past the horizon: it counts as having seen nothing
  // there too.
  EXPECT_EQ(NoReturnEnds(scan, 4.0f).size(), 2u);
}

TEST(LaserScanTest, SimulatedScanHitsBoxWalls) {
  const auto world = testing::BoxWorld({-2.0, -1.0}, {3.0, 1.0});
  const LaserScan scan = testing::SimulateScan(world, Rigid2d(0, 0, 0));
  ASSERT_EQ(scan.size(), 181);
  EXPECT_NEAR(scan.ranges[90], 3.0f, 1e-5f);  // straight ahead
  EXPECT_NEAR(scan.ranges[0], 1.0f, 1e-5f);   // right wall
  EXPECT_NEAR(scan.ranges[180], 1.0f, 1e-5f);  // left wall
}

}  // namespace
}  // namespace fleetmap

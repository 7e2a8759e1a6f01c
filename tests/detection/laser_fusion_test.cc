#include "robot_agent/detection/laser_fusion.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::AddCylinder;
using testing::SegmentWorld;

class LaserFusionTest : public ::testing::Test {
 protected:
  // A candidate as the image stage would report a marker at `position` (camera = robot frame).
  MarkerCandidate CandidateAt(const Eigen::Vector2d& position, double size_error = 1.05) {
    MarkerCandidate c;
    c.robot_id = "robot2";
    c.bearing_in_camera = std::atan2(position.y(), position.x());
    c.range_from_size = size_error * position.norm();
    c.angular_width = 2.0 * std::asin(geometry_.marker_radius / position.norm());
    c.position_in_robot = c.range_from_size * Eigen::Vector2d(std::cos(c.bearing_in_camera),
                                                              std::sin(c.bearing_in_camera));
    c.confidence = 0.9;
    return c;
  }

  CameraModel camera_;
  MarkerGeometry geometry_;
  LaserFusionOptions options_;
  SegmentWorld world_ = testing::BoxWorld({-1.0, -5.0}, {10.0, 5.0});
};

TEST_F(LaserFusionTest, MeasuresCylinderCentre) {
  const Eigen::Vector2d robot(4.0, 1.0);
  AddCylinder(robot, geometry_.body_radius, &world_);
  const LaserScan scan = testing::SimulateScan(world_, Rigid2d());
  const FusionResult result = FuseWithLaser(CandidateAt(robot), scan, camera_, geometry_, options_);
  ASSERT_EQ(result.status, FusionStatus::kConfirmed) << FusionStatusName(result.status);
  EXPECT_LT((result.detection.position_in_observer - robot).norm(), 0.005);
  EXPECT_GE(result.detection.laser_returns, 4);
  EXPECT_EQ(result.detection.observed_id, "robot2");
}

TEST_F(LaserFusionTest, SensorMountIsApplied) {
  const Eigen::Vector2d robot(3.0, -1.0);
  AddCylinder(robot, geometry_.body_radius, &world_);
  const Rigid2d sensor_in_robot(0.2, 0.05, 0.1);
  const LaserScan scan = testing::SimulateScan(world_, Rigid2d(), 181, -M_PI / 2, M_PI / 180,
                                               8.0f, sensor_in_robot);
  const FusionResult result = FuseWithLaser(CandidateAt(robot), scan, camera_, geometry_, options_);
  ASSERT_EQ(result.status, FusionStatus::kConfirmed) << FusionStatusName(result.status);
  EXPECT_LT((result.detection.position_in_observer - robot).norm(), 0.005);
}

TEST_F(LaserFusionTest, CovarianceGrowsWithRange) {
  AddCylinder({2.0, 0.5}, geometry_.body_radius, &world_);
  AddCylinder({7.0, -2.0}, geometry_.body_radius, &world_);
  const LaserScan scan = testing::SimulateScan(world_, Rigid2d());
  const FusionResult near = FuseWithLaser(CandidateAt({2.0, 0.5}), scan, camera_, geometry_, options_);
  const FusionResult far = FuseWithLaser(CandidateAt({7.0, -2.0}), scan, camera_, geometry_, options_);
  ASSERT_EQ(near.status, FusionStatus::kConfirmed);
  ASSERT_EQ(far.status, FusionStatus::kConfirmed);
  EXPECT_GT(near.detection.laser_returns, far.detection.laser_returns);
  EXPECT_GT(far.detection.covariance.trace(), 2.0 * near.detection.covariance.trace());
}

TEST_F(LaserFusionTest, PosterOnWallIsRejected) {
  // Nothing but the wall at x = 10 where the camera saw "a marker".
  const LaserScan scan = testing::SimulateScan(world_, Rigid2d());
  const FusionResult result =
      FuseWithLaser(CandidateAt({9.8, 0.0}, 1.0), scan, camera_, geometry_, options_);
  EXPECT_NE(result.status, FusionStatus::kConfirmed);
}

TEST_F(LaserFusionTest, BodyBesideTheMarkerBearingIsRejected) {
  // A robot 0.6 m to the side of where the camera saw the marker (a poster beside a robot).
  AddCylinder({4.0, 0.6}, geometry_.body_radius, &world_);
  const LaserScan scan = testing::SimulateScan(world_, Rigid2d());
  const FusionResult result = FuseWithLaser(CandidateAt({4.0, 0.0}), scan, camera_, geometry_, options_);
  EXPECT_NE(result.status, FusionStatus::kConfirmed);
}

TEST_F(LaserFusionTest, NoReturnsNearBearing) {
  SegmentWorld open = {{{3.0, 3.0}, {3.0, 4.0}}};  // one short wall far to the left
  const LaserScan scan = testing::SimulateScan(open, Rigid2d());
  const FusionResult result = FuseWithLaser(CandidateAt({4.0, -1.0}), scan, camera_, geometry_, options_);
  EXPECT_EQ(result.status, FusionStatus::kNoReturnsNearBearing);
}

TEST_F(LaserFusionTest, RangeMustAgreeWithApparentSize) {
  AddCylinder({3.0, 0.0}, geometry_.body_radius, &world_);
  const LaserScan scan = testing::SimulateScan(world_, Rigid2d());
  const FusionResult result =
      FuseWithLaser(CandidateAt({3.0, 0.0}, 2.5), scan, camera_, geometry_, options_);
  EXPECT_NE(result.status, FusionStatus::kConfirmed);
}

TEST_F(LaserFusionTest, BadScansAreRejected) {
  LaserScan empty;
  EXPECT_EQ(FuseWithLaser(CandidateAt({3.0, 0.0}), empty, camera_, geometry_, options_).status,
            FusionStatus::kBadScan);
  LaserScan nan_scan = testing::SimulateScan(world_, Rigid2d());
  nan_scan.angle_increment = std::nanf("");
  EXPECT_EQ(FuseWithLaser(CandidateAt({3.0, 0.0}), nan_scan, camera_, geometry_, options_).status,
            FusionStatus::kBadScan);
  LaserScan no_returns = testing::SimulateScan({}, Rigid2d());
  EXPECT_EQ(FuseWithLaser(CandidateAt({3.0, 0.0}), no_returns, camera_, geometry_, options_).status,
            FusionStatus::kNoReturnsNearBearing);
}

}  // namespace
}  // namespace fleetmap

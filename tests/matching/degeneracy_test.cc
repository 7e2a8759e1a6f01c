#include "shared/matching/degeneracy.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

std::vector<Eigen::Vector2f> ScanPoints(const testing::SegmentWorld& world) {
  return ToPointsInRobotFrame(testing::SimulateScan(world, Rigid2d(0.0, 0.0, 0.0), 181,
                                                    static_cast<float>(-M_PI / 2),
                                                    static_cast<float>(M_PI / 180), 8.0f));
}

TEST(DegeneracyTest, PlainCorridorLeavesItsAxisUnobserved) {
  // A corridor along x, 2 m wide, whose ends are out of range.
  const testing::SegmentWorld corridor =
      testing::BoxWorld(Eigen::Vector2d(-50.0, -1.0), Eigen::Vector2d(50.0, 1.0));
  const Eigen::Matrix2d scatter = NormalScatter(ScanPoints(corridor));
  EXPECT_LT(scatter(0, 0), 0.01);
  EXPECT_GT(scatter(1, 1), 0.9);
  // The match slid back along the axis: the odometry's x is kept, the observed y and the
  // rotation come from the match.
  const Rigid2d predicted(1.0, 0.0, 0.0), matched(0.95, 0.02, 0.01);
  const Rigid2d kept = KeepObservedDirections(predicted, matched, scatter, 0.03);
  EXPECT_NEAR(kept.x(), 1.0, 1e-3);
  EXPECT_NEAR(kept.y(), 0.02, 1e-3);
  EXPECT_NEAR(kept.rotation(), 0.01, 1e-12);
}

TEST(DegeneracyTest, RoomObservesBothDirections) {
  const testing::SegmentWorld room =
      testing::BoxWorld(Eigen::Vector2d(-1.0, -3.0), Eigen::Vector2d(4.0, 3.0));
  const Eigen::Matrix2d scatter = NormalScatter(ScanPoints(room));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  EXPECT_GT(solver.eigenvalues()(0), 0.1);
  const Rigid2d predicted(1.0, 0.0, 0.0), matched(0.95, 0.02, 0.01);
  EXPECT_THAT(KeepObservedDirections(predicted, matched, scatter, 0.03),
              testing::IsNearPose(matched, 1e-9, 1e-12));
}

}  // namespace
}  // namespace fleetmap

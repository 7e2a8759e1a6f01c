#include "robot_agent/slam/submap_builder.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

const testing::SegmentWorld kRoom =
    testing::BoxWorld(Eigen::Vector2d(-4.0, -3.0), Eigen::Vector2d(4.0, 3.0));

LaserScan ScanAt(const Rigid2d& pose, double time) {
  LaserScan scan = testing::SimulateScan(kRoom, pose);
  scan.timestamp = time;
  return scan;
}

// Five scans per submap, twelve scans inserted: two finished submaps and an active one.
SubmapBuilder TwelveScansFivePerSubmap() {
  SubmapOptions options;
  options.max_scans = 5;
  options.max_travel = 0.0;
  SubmapBuilder builder("r1", options);
  for (int i = 0; i < 12; ++i) builder.Insert(ScanAt(Rigid2d(0.01 * i, 0.0, 0.0), i), Rigid2d(0.01 * i, 0.0, 0.0));
  return builder;
}

TEST(SubmapBuilderTest, FinishesAfterTheConfiguredScanCount) {
  SubmapBuilder builder = TwelveScansFivePerSubmap();
  std::vector<Submap> updates = builder.TakeUpdates();
  ASSERT_EQ(updates.size(), 3u);  // two finished, one active with two scans
  EXPECT_TRUE(updates[0].finished);
  EXPECT_TRUE(updates[1].finished);
  EXPECT_FALSE(updates[2].finished);
  EXPECT_EQ(updates[0].submap_id, 0);
  EXPECT_EQ(updates[1].submap_id, 1);
  EXPECT_EQ(updates[0].scan_poses.size(), 5u);
  EXPECT_EQ(updates[2].scan_poses.size(), 2u);
  EXPECT_EQ(updates[0].robot_id, "r1");
  EXPECT_DOUBLE_EQ(updates[1].scan_poses.front().timestamp, 5.0);
  // Nothing changed since: nothing to report.
  EXPECT_TRUE(builder.TakeUpdates().empty());
  builder.FinishActive();
  updates = builder.TakeUpdates();
  ASSERT_EQ(updates.size(), 1u);
  EXPECT_TRUE(updates[0].finished);
  EXPECT_EQ(updates[0].submap_id, 2);
  EXPECT_GT(updates[0].revision, 0);
}

TEST(SubmapBuilderTest, HandsOutAtMostTheRequestedCountOldestFirst) {
  SubmapBuilder builder = TwelveScansFivePerSubmap();
  // Two finished and the active one are pending; one per call, in order, then nothing.
  for (int64_t id = 0; id < 3; ++id) {
    const std::vector<Submap> updates = builder.TakeUpdates(1);
    ASSERT_EQ(updates.size(), 1u) << "call " << id;
    EXPECT_EQ(updates[0].submap_id, id);
    EXPECT_EQ(updates[0].finished, id < 2);
  }
  EXPECT_TRUE(builder.TakeUpdates(1).empty());
}

TEST(SubmapBuilderTest, FinishesAfterTheConfiguredTravel) {
  SubmapOptions options;
  options.max_scans = 0;
  options.max_travel = 1.0;
  SubmapBuilder builder("r1", options);
  // 0.3 m per scan: the fifth scan (1.2 m after the first) finishes the first submap.
  for (int i = 0; i < 5; ++i) builder.Insert(ScanAt(Rigid2d(0.3 * i - 2.0, 0.0, 0.0), i), Rigid2d(0.3 * i - 2.0, 0.0, 0.0));
  const std::vector<Submap> updates = builder.TakeUpdates();
  ASSERT_EQ(updates.size(), 1u);
  EXPECT_TRUE(updates[0].finished);
  EXPECT_EQ(updates[0].scan_poses.size(), 5u);
}

TEST(SubmapBuilderTest, GridLivesInTheSubmapFrame) {
  SubmapBuilder builder("r1", SubmapOptions());
  const Rigid2d robot(1.0, 0.5, 0.3);
  builder.Insert(ScanAt(robot, 0.0), robot);
  const Submap* submap = builder.active();
  ASSERT_NE(submap, nullptr);
  EXPECT_THAT(submap->submap_in_local, IsNearPose(Rigid2d(1.0, 0.5, 0.0), 1e-12, 1e-12));
  // The wall at x = 4 (local frame) is occupied in the submap grid at x = 3.
  // (The end point lies on a cell boundary, so look at the cells on both sides.)
  const float wall = std::max(submap->grid.Probability(submap->grid.CellAt(Eigen::Vector2d(3.01, 0.0))),
                              submap->grid.Probability(submap->grid.CellAt(Eigen::Vector2d(2.99, 0.0))));
  EXPECT_GT(wall, 0.6);
  EXPECT_LT(submap->grid.Probability(submap->grid.CellAt(Eigen::Vector2d(1.5, 0.0))), 0.45);  // one miss: p = 0.40
}

TEST(SubmapBuilderTest, RevisionMovesPosesAndBumpsTheRevision) {
  SubmapBuilder builder("r1", SubmapOptions());
  builder.Insert(ScanAt(Rigid2d(0.0, 0.0, 0.0), 0.0), Rigid2d(0.0, 0.0, 0.0));
  builder.Insert(ScanAt(Rigid2d(0.5, 0.0, 0.0), 1.0), Rigid2d(0.5, 0.0, 0.0));
  const std::vector<Submap> first = builder.TakeUpdates();
  ASSERT_EQ(first.size(), 1u);
  ASSERT_TRUE(builder.Revise(0, Rigid2d(0.0, 1.0, 0.0)));
  EXPECT_FALSE(builder.Revise(42, Rigid2d()));
  const std::vector<Submap> second = builder.TakeUpdates();
  ASSERT_EQ(second.size(), 1u);
  EXPECT_GT(second[0].revision, first[0].revision);
  EXPECT_THAT(second[0].scan_poses[1].pose, IsNearPose(Rigid2d(0.5, 1.0, 0.0), 1e-12, 1e-12));
}

}  // namespace
}  // namespace fleetmap

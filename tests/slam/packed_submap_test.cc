#include "robot_agent/slam/packed_submap.h"

#include <gtest/gtest.h>

#include "robot_agent/slam/submap_builder.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

Submap RoomSubmap() {
  const testing::SegmentWorld room =
      testing::BoxWorld(Eigen::Vector2d(-4.0, -3.0), Eigen::Vector2d(4.0, 3.0));
  SubmapBuilder builder("r7", SubmapOptions());
  for (int i = 0; i < 10; ++i) {
    const Rigid2d pose(0.2 * i - 1.0, 0.1 * i, 0.05 * i);
    LaserScan scan = testing::SimulateScan(room, pose);
    scan.timestamp = i;
    builder.Insert(scan, pose);
  }
  builder.FinishActive();
  std::vector<Submap> submaps = builder.TakeUpdates();
  EXPECT_EQ(submaps.size(), 1u);
  return submaps.front();
}

TEST(PackedSubmapTest, UnpacksCellForCell) {
  const Submap submap = RoomSubmap();
  const PackedSubmap packed = PackSubmap(submap);
  EXPECT_TRUE(packed.header.grid.empty());
  const Submap unpacked = UnpackSubmap(packed);
  EXPECT_EQ(unpacked.robot_id, "r7");
  EXPECT_EQ(unpacked.submap_id, submap.submap_id);
  EXPECT_EQ(unpacked.revision, submap.revision);
  EXPECT_TRUE(unpacked.finished);
  EXPECT_THAT(unpacked.submap_in_local, testing::IsNearPose(submap.submap_in_local, 0.0, 0.0));
  ASSERT_EQ(unpacked.scan_poses.size(), submap.scan_poses.size());
  EXPECT_EQ(unpacked.grid.origin(), submap.grid.origin());
  EXPECT_EQ(unpacked.grid.width(), submap.grid.width());
  EXPECT_EQ(unpacked.grid.height(), submap.grid.height());
  EXPECT_EQ(unpacked.grid.resolution(), submap.grid.resolution());
  EXPECT_EQ(unpacked.grid.options().log_odds_hit, submap.grid.options().log_odds_hit);
  EXPECT_EQ(unpacked.grid.log_odds(), submap.grid.log_odds());
}

// The point of packing: a room's submap (mostly unknown cells and a few repeated values) keeps
// a small fraction of its float cells.
TEST(PackedSubmapTest, KeepsAFractionOfTheCells) {
  const Submap submap = RoomSubmap();
  const size_t raw = submap.grid.log_odds().size() * sizeof(float);
  const PackedSubmap packed = PackSubmap(submap);
  EXPECT_LT(packed.compressed_cells.capacity(), raw / 4) << "raw " << raw << " bytes";
}

TEST(PackedSubmapTest, EmptyGridRoundTrips) {
  Submap submap;
  submap.robot_id = "r1";
  const Submap unpacked = UnpackSubmap(PackSubmap(submap));
  EXPECT_TRUE(unpacked.grid.empty());
  EXPECT_EQ(unpacked.robot_id, "r1");
}

}  // namespace
}  // namespace fleetmap

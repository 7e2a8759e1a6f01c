#include "map_server/merge/whole_map_walls.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/merge/merge_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

constexpr double kResolution = 0.2;  // the merge engine's whole-map resolution

MatchTargetOptions WholeMapOptions() {
  MatchTargetOptions options;
  options.grid.resolution = kResolution;
  options.grid.sigma = 0.0;
  return options;
}

std::vector<Rigid2d> OfficeRooms() {
  return {Rigid2d(3.5, 6, 0), Rigid2d(5, 3, 0),    Rigid2d(10, 6, 0),
          Rigid2d(10, 10, 0), Rigid2d(10, 1.5, 0), Rigid2d(16, 6, 0)};
}

TrailMask NoTrails() { return TrailMask({}, 0.0, 0.05); }

// a maps the office in the world frame; b maps it from the same rooms in its own frame, which
// sits at `b_in_world`: b's map lies on a's at b_in_world.
class WholeMapWallsTest : public ::testing::Test {
 protected:
  const Rigid2d b_in_world_{Rigid2d(4.0, -3.0, 0.7)};
  const WholeMapWalls walls_{
      testing::GridFromScans(testing::OfficeWorld(), OfficeRooms(), Rigid2d(), kResolution),
      testing::GridFromScans(testing::OfficeWorld(), OfficeRooms(), b_in_world_, kResolution),
      WholeMapOptions(),
      NoTrails(),
      NoTrails(),
      WallCountOptions()};
};

TEST_F(WholeMapWallsTest, CentredAndWholeAlignmentsAreInverse) {
  const Rigid2d centred = walls_.Centred(b_in_world_);
  EXPECT_THAT(walls_.Whole(centred), IsNearPose(b_in_world_, 1e-9, 1e-9));
  // The centred map's points are b's, moved by its centroid.
  ASSERT_FALSE(walls_.points_b().coarse.empty());
  EXPECT_LT(
      (walls_.centred_b().coarse.front() + walls_.centroid_b() - walls_.points_b().coarse.front())
          .norm(),
      1e-9);
}

TEST_F(WholeMapWallsTest, TheTrueAlignmentCrossesNoSeenFreeSpace) {
  EXPECT_LE(walls_.Contradictions(walls_.Centred(b_in_world_), /*fitted=*/false), 3);
  EXPECT_LE(walls_.Contradictions(walls_.Centred(b_in_world_), /*fitted=*/true), 3);
}

// Shifted by 1.5 m along x, b's walls stand across the rooms a saw free, and a's across b's.
TEST_F(WholeMapWallsTest, AShiftedAlignmentCrossesSeenFreeSpace) {
  const Rigid2d shifted = Rigid2d(1.5, 0.0, 0.0) * b_in_world_;
  EXPECT_GE(walls_.Contradictions(walls_.Centred(shifted), /*fitted=*/false), 40);
  // A tile moves at most 0.4 m to fit: 1.5 m off is not local SLAM's drift.
  EXPECT_GE(walls_.Contradictions(walls_.Centred(shifted), /*fitted=*/true), 20);
  // Without trails nothing is excused.
  EXPECT_EQ(walls_.ContradictionsWithTrails(walls_.Centred(shifted)),
            walls_.Contradictions(walls_.Centred(shifted), /*fitted=*/true));
}

// Bodies on trails are not walls seen through: the whole office is on a trail of b's robots
// (a radius reaching every wall). b's own walls are all excused, a's (no trails of its own) none;
// aligned, a's walls land on b's trails too, so fewer count than with the trails' walls.
TEST_F(WholeMapWallsTest, WallsOnTheirOwnPartsTrailsAreExcused) {
  const std::vector<Rigid2d> rooms = OfficeRooms();
  std::vector<Eigen::Vector2d> trail_in_b;
  for (const Rigid2d& room : rooms)
    trail_in_b.push_back((b_in_world_.inverse() * room).translation());
  const OccupancyGrid map_a =
      testing::GridFromScans(testing::OfficeWorld(), rooms, Rigid2d(), kResolution);
  const OccupancyGrid map_b =
      testing::GridFromScans(testing::OfficeWorld(), rooms, b_in_world_, kResolution);
  const WholeMapWalls everywhere(map_a, map_b, WholeMapOptions(), NoTrails(),
                                 TrailMask(trail_in_b, 30.0, 0.05), WallCountOptions());
  EXPECT_TRUE(everywhere.WallsOffOwnTrailsB().empty());
  EXPECT_EQ(everywhere.WallsOffOwnTrailsA().size(), everywhere.points_a().fine.size());
  const Rigid2d shifted = everywhere.Centred(Rigid2d(1.5, 0.0, 0.0) * b_in_world_);
  EXPECT_GT(everywhere.ContradictionsWithTrails(shifted),
            everywhere.Contradictions(shifted, /*fitted=*/true));
}

}  // namespace
}  // namespace fleetmap

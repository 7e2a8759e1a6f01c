#include "shared/matching/seen_from_behind.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// Two corridors 2.4 m wide side by side, split by a 0.2 m wall along y = 0 (its faces at
// y = -0.1 and 0.1), closed at x = 0 and x = 12.
testing::SegmentWorld TwinCorridors() {
  testing::SegmentWorld world =
      testing::BoxWorld(Eigen::Vector2d(0.0, -2.5), Eigen::Vector2d(12.0, 2.5));
  testing::AddBox(Eigen::Vector2d(0.0, -0.1), Eigen::Vector2d(12.0, 0.1), &world);
  return world;
}

std::vector<Eigen::Vector2f> ScanAt(const testing::SegmentWorld& world, const Rigid2d& pose) {
  return ToPointsInRobotFrame(testing::SimulateScan(world, pose, 181, static_cast<float>(-M_PI / 2),
                                                    static_cast<float>(M_PI / 180), 8.0f));
}

// The map of the lower corridor, seen from inside it, as loop closure's targets are built.
MatchGrid LowerCorridorMap(const testing::SegmentWorld& world) {
  MatchGridOptions options;
  options.track_observed = true;
  MatchGrid grid(options);
  for (double x = 1.0; x <= 11.0; x += 2.0) {
    for (const double heading : {0.0, M_PI}) {
      const Rigid2d pose(Eigen::Vector2d(x, -1.3), heading);
      grid.AddPoints(ScanAt(world, pose), pose);
    }
  }
  return grid;
}

TEST(SeenFromBehindTest, AScanWhereItWasTakenSeesWallsFromTheFront) {
  const testing::SegmentWorld world = TwinCorridors();
  const MatchGrid map = LowerCorridorMap(world);
  for (const Rigid2d& pose :
       {Rigid2d(Eigen::Vector2d(3.0, -1.3), 0.0), Rigid2d(Eigen::Vector2d(6.0, -0.8), 2.0),
        Rigid2d(Eigen::Vector2d(9.5, -1.6), -2.8)}) {
    const SeenFromBehind judged =
        WallsSeenFromBehind(ScanAt(world, pose), Eigen::Vector2d::Zero(), map, pose);
    EXPECT_GT(judged.on_walls, 100) << pose;
    EXPECT_LT(judged.fraction(), 0.1) << pose;
  }
}

TEST(SeenFromBehindTest, AScanOfTheOtherCorridorPlacedInThisOneIsSeenFromBehind) {
  const testing::SegmentWorld world = TwinCorridors();
  const MatchGrid map = LowerCorridorMap(world);
  // A scan taken in the upper corridor facing +x, at the end wall x = 12 ...
  const Rigid2d taken(Eigen::Vector2d(8.0, 1.3), 0.0);
  const std::vector<Eigen::Vector2f> points = ScanAt(world, taken);
  // ... slid down by the wall's thickness: its view of the split wall's upper face (y = 0.1)
  // lands exactly on the lower face (y = -0.1) that the map saw from below.
  const Rigid2d placed(taken.translation() - Eigen::Vector2d(0.0, 0.2), taken.rotation());
  const SeenFromBehind judged = WallsSeenFromBehind(points, Eigen::Vector2d::Zero(), map, placed);
  EXPECT_GT(judged.on_walls, 20);
  EXPECT_GT(judged.fraction(), 0.5);
}

TEST(SeenFromBehindTest, NothingIsBehindInAGridThatDoesNotTrackWhatItSaw) {
  const testing::SegmentWorld world = TwinCorridors();
  MatchGrid untracked;
  const Rigid2d pose(Eigen::Vector2d(3.0, -1.3), 0.0);
  untracked.AddPoints(ScanAt(world, pose), pose);
  const Rigid2d placed(Eigen::Vector2d(8.0, 1.1), 0.0);
  EXPECT_EQ(WallsSeenFromBehind(ScanAt(world, Rigid2d(Eigen::Vector2d(8.0, 1.3), 0.0)),
                                Eigen::Vector2d::Zero(), untracked, placed)
                .behind,
            0);
  EXPECT_EQ(WallsSeenFromBehind({}, Eigen::Vector2d::Zero(), untracked, pose).fraction(), 0.0);
}

}  // namespace
}  // namespace fleetmap

// Walls a robot's body explains (trail_walls.h): blobs of wall cells wholly on where a robot
// drove.

#include "map_server/merge/trail_walls.h"

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

// A straight trail along y = 0 from x = 0 to x = 10.
std::vector<Eigen::Vector2d> StraightTrail() {
  std::vector<Eigen::Vector2d> positions;
  for (double x = 0.0; x <= 10.0; x += 0.05) positions.emplace_back(x, 0.0);
  return positions;
}

TEST(TrailMaskTest, HoldsWhatLiesWithinTheRadiusOfAPosition) {
  const TrailMask trail(StraightTrail(), 0.4, 0.05);
  EXPECT_TRUE(trail.Contains({5.0, 0.0}));
  EXPECT_TRUE(trail.Contains({5.0, 0.33}));
  EXPECT_TRUE(trail.Contains({5.0, -0.33}));
  EXPECT_TRUE(trail.Contains({10.3, 0.0}));
  EXPECT_FALSE(trail.Contains({5.0, 0.5}));
  EXPECT_FALSE(trail.Contains({10.5, 0.0}));
  EXPECT_FALSE(trail.Contains({-3.0, 40.0}));
  EXPECT_FALSE(TrailMask({}, 0.4, 0.05).Contains({0.0, 0.0}));
}

// A 0.2 m grid over [-2, 12] x [-3, 3], all seen free, with walls set cell by cell.
OccupancyGrid FreeGrid() {
  OccupancyGridOptions options;
  options.resolution = 0.2;
  OccupancyGrid grid(options);
  grid.GrowToInclude({-2.0, -3.0}, {12.0, 3.0});
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) grid.SetLogOdds(CellIndex(x, y), -2.0f);
  }
  return grid;
}

void SetWall(const Eigen::Vector2d& point, OccupancyGrid* grid) {
  grid->SetLogOdds(grid->CellAt(point), 2.0f);
}

TEST(WallBlobsTest, ABodyOnTheTrailIsOnItAndAWallAcrossItIsNot) {
  OccupancyGrid grid = FreeGrid();
  // A body: a 0.4 m square on the trail.
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(3.1, -0.1), Eigen::Vector2d(3.3, -0.1),
                                   Eigen::Vector2d(3.1, 0.1), Eigen::Vector2d(3.3, 0.1)}) {
    SetWall(p, &grid);
  }
  // A wall crossing the trail at x = 7, from y = -2 to y = 2.
  for (double y = -1.9; y < 2.0; y += 0.2) SetWall({7.1, y}, &grid);
  const WallBlobs blobs(grid, 0.0f);
  ASSERT_EQ(blobs.size(), 2);
  const int body = blobs.BlobAt({3.2, 0.0}), wall = blobs.BlobAt({7.1, 1.5});
  ASSERT_GE(body, 0);
  ASSERT_GE(wall, 0);
  EXPECT_NE(body, wall);
  EXPECT_EQ(blobs.BlobAt({5.0, 0.0}), -1) << "seen free";
  EXPECT_EQ(blobs.BlobAt({50.0, 0.0}), -1) << "outside the grid";
  EXPECT_EQ(blobs.BlobAt({7.1, -1.7}), wall) << "one wall, one blob";

  const TrailMask trail(StraightTrail(), 0.35 + 0.2 * M_SQRT1_2, 0.05);
  const std::vector<bool> on = blobs.OnTrails(trail, Rigid2d());
  EXPECT_TRUE(on[body]);
  EXPECT_FALSE(on[wall]) << "robots do not drive through walls";
  // The same grid placed 1 m to the side: the body is off the trail.
  EXPECT_FALSE(blobs.OnTrails(trail, Rigid2d(0.0, 1.0, 0.0))[body]);
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/sim/map_accuracy.h"

#include <gtest/gtest.h>

#include "robot_agent/sim/world_builder.h"

namespace fleetmap::sim {
namespace {

// A 4 x 3 m room (blocked outside the carved box). Of the map's three occupied cells, one lies
// on the west wall and one a cell inside the room (within one cell: counted), one in the middle
// of the room; a free cell is not scored. Moved 1 m into the room, none lies on a wall.
TEST(MapAccuracyTest, CountsOccupiedCellsWithinOneCellOfAWall) {
  WorldBuilder builder("room", 0.05, Eigen::Vector2d(4.0, 3.0));
  builder.Carve({0.5, 0.5}, {3.5, 2.5});
  const World world = builder.Build();
  ASSERT_TRUE(world.IsBlockedAt({0.45, 1.5}));
  ASSERT_FALSE(world.IsBlockedAt({0.6, 1.5}));

  OccupancyGrid map;
  map.SetLogOdds(map.CellAt({0.47, 1.5}), 2.0f);  // on the wall
  map.SetLogOdds(map.CellAt({0.52, 1.0}), 2.0f);  // one cell inside the room: still within 1 cell
  map.SetLogOdds(map.CellAt({2.0, 1.5}), 2.0f);   // in the middle of the room
  map.SetLogOdds(map.CellAt({2.0, 1.0}), -2.0f);  // free: not scored
  const MapAccuracy exact = ScoreAgainstWalls(map, Rigid2d(), world);
  EXPECT_EQ(exact.occupied, 3);
  EXPECT_EQ(exact.near_wall, 2);
  EXPECT_NEAR(exact.fraction(), 2.0 / 3.0, 1e-12);

  const MapAccuracy moved = ScoreAgainstWalls(map, Rigid2d(1.0, 0.0, 0.0), world);
  EXPECT_EQ(moved.occupied, 3);
  EXPECT_EQ(moved.near_wall, 0);
  EXPECT_EQ(MapAccuracy().fraction(), 0.0);
}

}  // namespace
}  // namespace fleetmap::sim

#include "robot_agent/sim/map_accuracy.h"

#include <gtest/gtest.h>

#include "robot_agent/sim/world_builder.h"
#include "robot_agent/sim/world_io.h"
#include "shared/io/map_file.h"
#include "tests/support/test_support.h"

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
  const WallScore exact = ScoreOnWalls(map, Rigid2d(), WorldWalls(world));
  EXPECT_EQ(exact.occupied, 3);
  EXPECT_EQ(exact.near_wall, 2);
  EXPECT_NEAR(exact.fraction(), 2.0 / 3.0, 1e-12);

  const WallScore moved = ScoreOnWalls(map, Rigid2d(1.0, 0.0, 0.0), WorldWalls(world));
  EXPECT_EQ(moved.occupied, 3);
  EXPECT_EQ(moved.near_wall, 0);
  EXPECT_EQ(WallScore().fraction(), 0.0);
}

// Thin walls in an open hall, and a map of them whose frame is 0.17 m and 0.25 degrees off the
// world's: placed there it scores poorly, at the best fit every wall cell is on a wall again.
TEST(MapAccuracyTest, BestFitFindsThePlacementOfAShiftedMap) {
  WorldBuilder builder("hall", 0.05, Eigen::Vector2d(6.0, 5.0));
  builder.Carve({0.1, 0.1}, {5.9, 4.9});
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls = {
      {{1.0, 1.0}, {5.0, 1.05}},
      {{1.0, 1.0}, {1.05, 4.0}},
      {{3.0, 2.5}, {5.0, 2.55}},
      {{4.0, 1.0}, {4.05, 2.0}}};
  for (const auto& [min, max] : walls) builder.Fill(min, max);
  const World world = builder.Build();
  const Rigid2d map_in_world(0.14, -0.1, 0.25 * M_PI / 180.0);
  OccupancyGrid map;
  for (const auto& [min, max] : walls) {
    for (double x = min.x() + 0.025; x < max.x(); x += 0.05) {
      for (double y = min.y() + 0.025; y < max.y(); y += 0.05) {
        map.SetLogOdds(map.CellAt(map_in_world.inverse() * Eigen::Vector2d(x, y)), 2.0f);
      }
    }
  }
  const WallMask world_walls = WorldWalls(world);
  EXPECT_LT(ScoreOnWalls(map, Rigid2d(), world_walls).fraction(), 0.3);
  Rigid2d best;
  const WallScore fitted = ScoreOnWallsBestFit(map, Rigid2d(), world_walls, &best);
  EXPECT_GT(fitted.fraction(), 0.99);
  // Within one cell every placement near the true one scores alike; the best found is one of
  // them, and scores the same by the plain rule.
  EXPECT_NEAR(best.translation().x(), 0.14, 0.1);
  EXPECT_NEAR(best.translation().y(), -0.1, 0.1);
  const WallScore again = ScoreOnWalls(map, best, world_walls);
  EXPECT_EQ(again.near_wall, fitted.near_wall);
  EXPECT_EQ(again.occupied, fitted.occupied);
}

// The benchmarks score against the simulator's world in memory, `fleetmapctl evaluate` against
// the world's PGM as the simulator writes it: both read the same walls, every point alike.
TEST(MapAccuracyTest, TheWorldAndItsFileHaveTheSameWalls) {
  WorldBuilder builder("office", 0.05, Eigen::Vector2d(6.0, 4.0));
  builder.Carve({0.5, 0.5}, {5.5, 3.5});
  builder.Fill({2.0, 0.5}, {2.1, 2.5});
  const World world = builder.Build();
  const testing::ScopedTempDir temp("fleetmap-walls");
  const std::string& dir = temp.path();
  std::string error;
  ASSERT_TRUE(SaveWorld(dir, world, &error)) << error;
  OccupancyGrid read;
  ASSERT_TRUE(ReadMap(dir + "/office.yaml", &read, &error)) << error;
  for (const int reach : {1, 2}) {
    const WallMask in_memory = WorldWalls(world, reach);
    const WallMask from_file = WallMask::FromTrueMap(read, reach);
    int near = 0;
    for (double y = -0.3; y < 4.3; y += 0.0173) {
      for (double x = -0.3; x < 6.3; x += 0.0173) {
        const Eigen::Vector2d p(x, y);
        ASSERT_EQ(in_memory.NearWall(p), from_file.NearWall(p)) << x << " " << y;
        near += in_memory.NearWall(p);
      }
    }
    EXPECT_GT(near, 1000);
  }
}

}  // namespace
}  // namespace fleetmap::sim

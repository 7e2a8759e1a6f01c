#include "shared/eval/wall_score.h"

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

OccupancyGrid Grid100() {
  OccupancyGridOptions options;
  options.resolution = 0.05;
  return OccupancyGrid(options, Eigen::Vector2d(0, 0), 100, 100);
}

// A true wall along row 50 (y from 2.50 to 2.55). Of the map's 100 occupied cells, 90 lie on it
// and 10 1.5 m off: 0.9 in place, 0 moved 1 m off, 0.9 again at the best fit of a map 0.12 m off.
TEST(WallScoreTest, CountsOccupiedCellsOnTrueWalls) {
  OccupancyGrid truth = Grid100();
  for (int i = 0; i < 100; ++i) truth.SetLogOdds(CellIndex(i, 50), 4.0f);
  const WallMask walls = WallMask::FromTrueMap(truth);
  OccupancyGrid map = Grid100();
  for (int i = 0; i < 90; ++i) map.SetLogOdds(CellIndex(i, 50), 4.0f);
  for (int i = 0; i < 10; ++i) map.SetLogOdds(CellIndex(i, 80), 4.0f);
  map.SetLogOdds(CellIndex(5, 5), -4.0f);  // free: not scored

  const WallScore exact = ScoreOnWalls(map, Rigid2d(), walls);
  EXPECT_EQ(exact.occupied, 100);
  EXPECT_EQ(exact.near_wall, 90);
  EXPECT_NEAR(exact.fraction(), 0.9, 1e-12);
  EXPECT_EQ(ScoreOnWalls(map, Rigid2d(0, 1.0, 0), walls).near_wall, 0);
  EXPECT_EQ(ScoreOnWalls(map, Rigid2d(0, 0.12, 0), walls).near_wall, 0);
  Rigid2d best;
  EXPECT_NEAR(ScoreOnWallsBestFit(map, Rigid2d(0, 0.12, 0), walls, &best).fraction(), 0.9, 1e-12);
  EXPECT_NEAR(best.translation().y(), 0.0, 0.051);
  EXPECT_EQ(WallScore().fraction(), 0.0);
}

// "Within one cell": the wall cell and its 8 neighbours, diagonal ones included; two cells off
// counts only with a reach of 2.
TEST(WallScoreTest, ReachCountsTheCellsAroundAWallCell) {
  OccupancyGrid truth = Grid100();
  truth.SetLogOdds(CellIndex(50, 50), 4.0f);
  const WallMask one = WallMask::FromTrueMap(truth);
  const WallMask two = WallMask::FromTrueMap(truth, 2);
  const auto center = [&](int x, int y) { return truth.CellCenter(CellIndex(x, y)); };
  EXPECT_TRUE(one.NearWall(center(50, 50)));
  EXPECT_TRUE(one.NearWall(center(51, 50)));
  EXPECT_TRUE(one.NearWall(center(49, 51)));  // diagonal
  EXPECT_FALSE(one.NearWall(center(52, 50)));
  EXPECT_FALSE(one.NearWall(center(50, 48)));
  EXPECT_TRUE(two.NearWall(center(52, 50)));
  EXPECT_TRUE(two.NearWall(center(48, 52)));
  EXPECT_FALSE(two.NearWall(center(53, 50)));
}

// Unknown truth cells and points beyond the truth's grid are not walls: a misplaced map cell
// that lands there is wrong. Map cells the exported map would not show occupied (p <= 0.65)
// are not scored.
TEST(WallScoreTest, UnknownCellsAndFaintMapCellsDoNotCount) {
  OccupancyGrid truth = Grid100();
  for (int i = 0; i < 100; ++i) truth.SetLogOdds(CellIndex(i, 0), -4.0f);  // free row
  truth.SetLogOdds(CellIndex(10, 10), 4.0f);
  const WallMask walls = WallMask::FromTrueMap(truth);
  EXPECT_TRUE(walls.NearWall(truth.CellCenter(CellIndex(10, 10))));
  EXPECT_FALSE(walls.NearWall(truth.CellCenter(CellIndex(30, 30))));  // unknown
  EXPECT_FALSE(walls.NearWall(Eigen::Vector2d(-1.0, 0.5)));           // beyond the grid
  EXPECT_FALSE(walls.NearWall(Eigen::Vector2d(5.1, 0.5)));

  OccupancyGrid map = Grid100();
  map.SetLogOdds(CellIndex(10, 10), ProbabilityToLogOdds(0.9f));
  map.SetLogOdds(CellIndex(40, 40), ProbabilityToLogOdds(0.6f));  // faint: not occupied
  const WallScore score = ScoreOnWalls(map, Rigid2d(), walls);
  EXPECT_EQ(score.occupied, 1);
  EXPECT_EQ(score.near_wall, 1);
}

}  // namespace
}  // namespace fleetmap

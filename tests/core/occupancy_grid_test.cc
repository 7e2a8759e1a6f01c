#include "shared/core/occupancy_grid.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(OccupancyGridTest, CellGeometry) {
  OccupancyGridOptions options;
  options.resolution = 0.1;
  const OccupancyGrid grid(options, Eigen::Vector2d(-1.0, -2.0), 20, 40);
  EXPECT_TRUE((grid.CellAt({-1.0, -2.0}) == CellIndex(0, 0)).all());
  EXPECT_TRUE((grid.CellAt({-0.95, -1.85}) == CellIndex(0, 1)).all());
  EXPECT_TRUE((grid.CellAt({-1.01, -2.0}) == CellIndex(-1, 0)).all());
  EXPECT_NEAR((grid.CellCenter({0, 0}) - Eigen::Vector2d(-0.95, -1.95)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(grid.IsKnown({3, 3}));
  EXPECT_FLOAT_EQ(grid.Probability({3, 3}), 0.5f);
  EXPECT_FLOAT_EQ(grid.Probability({-5, 300}), 0.5f);
}

TEST(OccupancyGridTest, GrowsKeepingContent) {
  OccupancyGrid grid;
  grid.SetLogOdds(grid.CellAt({0.0, 0.0}), 2.0f);
  grid.SetLogOdds(grid.CellAt({-20.0, 15.0}), -1.0f);
  grid.SetLogOdds(grid.CellAt({30.0, -7.0}), 1.5f);
  EXPECT_FLOAT_EQ(grid.LogOdds(grid.CellAt({0.0, 0.0})), 2.0f);
  EXPECT_FLOAT_EQ(grid.LogOdds(grid.CellAt({-20.0, 15.0})), -1.0f);
  EXPECT_FLOAT_EQ(grid.LogOdds(grid.CellAt({30.0, -7.0})), 1.5f);
  EXPECT_GE(grid.width() * grid.resolution(), 50.0);
  CellIndex lo, hi;
  ASSERT_TRUE(grid.KnownBounds(&lo, &hi));
  EXPECT_NEAR(grid.CellCenter(lo).x(), -20.0, 0.05);
  EXPECT_NEAR(grid.CellCenter(hi).x(), 30.0, 0.05);
}

// Each bound comes from a different row and cell: the leftmost and rightmost known cells of
// rows whose other cells are unknown, and a row with a single known cell in its middle.
TEST(OccupancyGridTest, KnownBoundsTakeEveryRowsFirstAndLastKnownCell) {
  OccupancyGridOptions options;
  options.resolution = 1.0;
  OccupancyGrid grid(options, Eigen::Vector2d(0, 0), 20, 10);
  grid.SetLogOdds(CellIndex(7, 2), 1.0f);
  grid.SetLogOdds(CellIndex(3, 5), -1.0f);
  grid.SetLogOdds(CellIndex(9, 5), 1.0f);
  grid.SetLogOdds(CellIndex(16, 6), 1.0f);
  grid.SetLogOdds(CellIndex(10, 8), 1.0f);
  CellIndex lo, hi;
  ASSERT_TRUE(grid.KnownBounds(&lo, &hi));
  EXPECT_EQ(lo.x(), 3);
  EXPECT_EQ(lo.y(), 2);
  EXPECT_EQ(hi.x(), 16);
  EXPECT_EQ(hi.y(), 8);
  grid.SetLogOdds(CellIndex(0, 9), 1.0f);
  grid.SetLogOdds(CellIndex(19, 0), 1.0f);
  ASSERT_TRUE(grid.KnownBounds(&lo, &hi));
  EXPECT_EQ(lo.x(), 0);
  EXPECT_EQ(lo.y(), 0);
  EXPECT_EQ(hi.x(), 19);
  EXPECT_EQ(hi.y(), 9);
}

TEST(OccupancyGridTest, EmptyGridHasNoKnownBounds) {
  OccupancyGrid grid;
  CellIndex lo, hi;
  EXPECT_FALSE(grid.KnownBounds(&lo, &hi));
}

// A 4 m x 3 m room scanned with 360 beams from its centre: walls occupied, inside free,
// outside unknown.
TEST(OccupancyGridTest, RayTracedRoomHasKnownAnswer) {
  // Walls run through cell centres, so every hit lands in the wall's own cell row or column.
  const auto world = testing::BoxWorld({-2.025, -1.525}, {2.025, 1.525});
  OccupancyGrid grid;
  for (double heading : {0.0, M_PI / 2, M_PI, -M_PI / 2}) {
    grid.InsertScan(testing::SimulateScan(world, Rigid2d(0.03, 0.02, heading), 181), Rigid2d(0.03, 0.02, heading));
  }
  // Walls: the cells just inside each wall line are hit.
  int wall_cells = 0, occupied_wall_cells = 0;
  for (double x = -1.9; x <= 1.9; x += 0.05) {
    for (double y : {-1.525, 1.525}) {
      ++wall_cells;
      occupied_wall_cells += grid.Probability(grid.CellAt({x, y})) > 0.6f ? 1 : 0;
    }
  }
  EXPECT_GE(occupied_wall_cells, wall_cells * 95 / 100);
  // The interior is free.
  int interior = 0, free_interior = 0;
  for (double x = -1.8; x <= 1.8; x += 0.1) {
    for (double y = -1.3; y <= 1.3; y += 0.1) {
      ++interior;
      const float p = grid.Probability(grid.CellAt({x, y}));
      free_interior += p < 0.4f ? 1 : 0;
      EXPECT_LE(p, 0.5f) << "interior cell marked occupied at " << x << "," << y;
    }
  }
  // 1-degree beams leave a few far cells between rays untouched; none may be marked occupied.
  EXPECT_GE(free_interior, interior * 97 / 100);
  // Outside was never seen.
  EXPECT_FALSE(grid.IsKnown(grid.CellAt({2.5, 0.0})));
  EXPECT_FALSE(grid.IsKnown(grid.CellAt({0.0, -2.0})));
}

TEST(OccupancyGridTest, NoReturnBeamsMarkNothingOccupied) {
  LaserScan scan = MakeLaserScan(0.0, 0.0f, 0.01f, 0.0f, 5.0f, std::vector<float>(50, 100.0f));
  OccupancyGrid skip;
  skip.InsertScan(scan, Rigid2d());
  CellIndex lo, hi;
  EXPECT_FALSE(skip.KnownBounds(&lo, &hi));

  OccupancyGridOptions options;
  options.no_return_free_distance = 2.0f;
  OccupancyGrid clear(options);
  clear.InsertScan(scan, Rigid2d());
  ASSERT_TRUE(clear.KnownBounds(&lo, &hi));
  for (float v : clear.log_odds()) EXPECT_LE(v, 0.0f);
  EXPECT_LT(clear.Probability(clear.CellAt({1.0, 0.1})), 0.5f);
  EXPECT_FALSE(clear.IsKnown(clear.CellAt({2.5, 0.0})));
}

// A masked beam (a return taken out, e.g. off another robot) is neither a hit nor free space,
// also where no-return beams clear space.
TEST(OccupancyGridTest, MaskedBeamsMarkNothing) {
  LaserScan scan = MakeLaserScan(0.0, 0.0f, 0.01f, 0.0f, 5.0f, std::vector<float>(50, 1.0f));
  for (float& r : scan.ranges) r = LaserScan::kMasked;
  ASSERT_TRUE(scan.IsMasked(0));
  ASSERT_FALSE(scan.IsReturn(0));
  OccupancyGridOptions options;
  options.no_return_free_distance = 2.0f;
  OccupancyGrid grid(options);
  grid.InsertScan(scan, Rigid2d());
  CellIndex lo, hi;
  EXPECT_FALSE(grid.KnownBounds(&lo, &hi));
}

TEST(OccupancyGridTest, MountOffsetMovesTheRays) {
  // A single beam straight ahead hitting 1 m from a sensor mounted 0.5 m ahead of the robot.
  const LaserScan scan = MakeLaserScan(0.0, 0.0f, 0.1f, 0.0f, 10.0f, {1.0f}, Rigid2d(0.5, 0.0, 0.0));
  OccupancyGrid grid;
  grid.InsertScan(scan, Rigid2d(1.0, 1.0, M_PI / 2));
  EXPECT_GT(grid.Probability(grid.CellAt({1.0, 2.52})), 0.6f);
  EXPECT_LT(grid.Probability(grid.CellAt({1.0, 1.75})), 0.5f);
  EXPECT_FALSE(grid.IsKnown(grid.CellAt({1.0, 1.2})));  // behind the sensor
}

TEST(OccupancyGridTest, LogOddsAreClamped) {
  const LaserScan scan = MakeLaserScan(0.0, 0.0f, 0.1f, 0.0f, 10.0f, {1.0f});
  OccupancyGrid grid;
  for (int i = 0; i < 100; ++i) grid.InsertScan(scan, Rigid2d());
  EXPECT_FLOAT_EQ(grid.LogOdds(grid.CellAt({1.01, 0.0})), grid.options().log_odds_max);
  EXPECT_FLOAT_EQ(grid.LogOdds(grid.CellAt({0.5, 0.0})), grid.options().log_odds_min);
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/slam/submap_assembly.h"

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

// A submap whose grid holds one occupied cell around `point` (submap frame), placed at `anchor`.
Submap OneWallCell(const Eigen::Vector2d& point, const Rigid2d& anchor) {
  Submap submap;
  submap.submap_in_local = anchor;
  submap.grid = OccupancyGrid(OccupancyGridOptions());
  submap.grid.SetLogOdds(submap.grid.CellAt(point), 2.0f);
  return submap;
}

TEST(SubmapAssemblyTest, PlacesEachSubmapAtItsAnchor) {
  const Submap shifted = OneWallCell(Eigen::Vector2d(1.025, 0.025), Rigid2d(2.0, 0.0, 0.0));
  const Submap turned = OneWallCell(Eigen::Vector2d(1.025, 0.025), Rigid2d(0.0, 0.0, M_PI / 2));
  const OccupancyGrid map = AssembleSubmaps({&shifted, &turned}, OccupancyGridOptions());
  // (1.025, 0.025) moved by 2 m along x, and turned a quarter about the origin.
  EXPECT_FLOAT_EQ(map.LogOdds(map.CellAt(Eigen::Vector2d(3.025, 0.025))), 2.0f);
  EXPECT_FLOAT_EQ(map.LogOdds(map.CellAt(Eigen::Vector2d(-0.025, 1.025))), 2.0f);
  EXPECT_FLOAT_EQ(map.LogOdds(map.CellAt(Eigen::Vector2d(1.025, 0.025))), 0.0f);
}

TEST(SubmapAssemblyTest, OverlappingSubmapsAddTheirLogOdds) {
  const Submap a = OneWallCell(Eigen::Vector2d(0.525, 0.525), Rigid2d());
  const Submap b = OneWallCell(Eigen::Vector2d(0.025, 0.025), Rigid2d(0.5, 0.5, 0.0));
  OccupancyGrid map(OccupancyGridOptions{});
  AddSubmapToAssembly(a, &map);  // one at a time, as fleetmap-slam unpacks them
  AddSubmapToAssembly(b, &map);
  EXPECT_FLOAT_EQ(map.LogOdds(map.CellAt(Eigen::Vector2d(0.525, 0.525))), 4.0f);
}

}  // namespace
}  // namespace fleetmap

#include <gtest/gtest.h>

#include "map_server/ctl/map_diff.h"
#include "map_server/server/global_map_renderer.h"
#include "map_server/server/grid_region.h"
#include "tests/server/server_test_util.h"

namespace fleetmap {
namespace {

TEST(GlobalMapRendererTest, PlacesSubmapAtItsPose) {
  const OccupancyGrid submap = testing::MakeRoomGrid(40);  // 2 m x 2 m, wall along y = 1.95
  OccupancyGrid canvas;
  // Rotated by 90 degrees and moved: the wall (submap y ~ 1.975) lands at global x ~ 10 - 1.975.
  const Rigid2d submap_in_global(10.0, 5.0, M_PI / 2);
  FuseSubmap(submap, submap_in_global, 1.0f, &canvas);
  EXPECT_NEAR(canvas.LogOdds(canvas.CellAt(Eigen::Vector2d(10.0 - 1.975, 6.0))), 3.0f, 1e-3);
  EXPECT_NEAR(canvas.LogOdds(canvas.CellAt(Eigen::Vector2d(9.0, 6.0))), -2.0f, 1e-3);
  EXPECT_EQ(canvas.LogOdds(canvas.CellAt(Eigen::Vector2d(11.0, 6.0))), 0.0f);
  // Adding twice sums, removing once leaves one contribution.
  FuseSubmap(submap, submap_in_global, 1.0f, &canvas);
  FuseSubmap(submap, submap_in_global, -1.0f, &canvas);
  EXPECT_NEAR(canvas.LogOdds(canvas.CellAt(Eigen::Vector2d(9.0, 6.0))), -2.0f, 1e-3);
}

QuantizedGrid Checker(int w, int h) {
  QuantizedGrid grid;
  grid.geometry.width = w;
  grid.geometry.height = h;
  grid.geometry.resolution = 0.1;
  grid.geometry.origin = Eigen::Vector2d(-1.0, -1.0);
  grid.cells.assign(static_cast<size_t>(w * h), -20);
  grid.cells[5 * w + 5] = 20;  // one occupied cell at (-0.45, -0.45)
  return grid;
}

TEST(GridRegionTest, CropsAndCoarsensOccupiedWins) {
  const QuantizedGrid map = Checker(20, 20);
  QuantizedGrid region;
  RegionError code;
  std::string error;
  RegionQuery query;
  query.box = std::make_pair(Eigen::Vector2d(-0.6, -0.6), Eigen::Vector2d(0.0, 0.0));
  ASSERT_TRUE(ExtractRegion(map, query, &region, &code, &error)) << error;
  EXPECT_EQ(region.geometry.width, 6);
  EXPECT_NEAR(region.geometry.origin.x(), -0.6, 1e-9);
  EXPECT_EQ(region.cells[1 * 6 + 1], 20);
  query.box.reset();
  query.resolution = 0.4;
  ASSERT_TRUE(ExtractRegion(map, query, &region, &code, &error)) << error;
  EXPECT_EQ(region.geometry.width, 5);
  EXPECT_EQ(region.cells[1 * 5 + 1], 20);  // the occupied cell survives coarsening
  EXPECT_EQ(region.cells[0], -20);
  query.resolution = 0.001;
  query.max_cells = 1000;
  EXPECT_FALSE(ExtractRegion(map, query, &region, &code, &error));
  EXPECT_EQ(code, RegionError::kTooLarge);
}

TEST(MapDiffTest, CountsChangedCells) {
  QuantizedGrid before = Checker(10, 10);
  QuantizedGrid after = before;
  after.cells[0] = 20;   // free -> occupied
  after.cells[1] = 0;    // free -> unknown
  const MapDiff diff = DiffMaps(before, after);
  EXPECT_EQ(diff.changed, 2);
  EXPECT_EQ(diff.became_occupied, 1);
  EXPECT_EQ(diff.became_unknown, 1);
  EXPECT_EQ(diff.rgb.size(), 10u * 10u * 3u);
}

}  // namespace
}  // namespace fleetmap

// The rectangle's size measured on points and on a map's cells (table I of the paper): known
// walls give their size back, a few stray points do not move them, and the cells are only as
// exact as their size.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "robot_agent/bench/map_extent.h"

namespace fleetmap {
namespace {

// Points on the inner faces of walls enclosing [x0, x1] x [y0, y1], with range-like noise, and
// an inner wall (a room's) that must not count as an outer one.
std::vector<Eigen::Vector2d> RectanglePoints(double x0, double y0, double x1, double y1, double noise) {
  std::mt19937 random(7);
  std::normal_distribution<double> n(0.0, noise);
  std::vector<Eigen::Vector2d> points;
  for (double t = 0.0; t <= 1.0; t += 0.0005) {
    const double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
    points.emplace_back(x, y0 + n(random));
    points.emplace_back(x, y1 + n(random));
    points.emplace_back(x0 + n(random), y);
    points.emplace_back(x1 + n(random), y);
    points.emplace_back(x0 + 2.0 + n(random), y0 + 0.5 * t * (y1 - y0));
  }
  return points;
}

TEST(MapExtentTest, PointsOnKnownWallsGiveTheirSize) {
  const auto extent = MeasureOuterWalls(RectanglePoints(1.1, -2.3, 22.0, 14.3, 0.01));
  ASSERT_TRUE(extent);
  EXPECT_NEAR(extent->size().x(), 20.9, 0.002);
  EXPECT_NEAR(extent->size().y(), 16.6, 0.002);
  EXPECT_NEAR(extent->min.x(), 1.1, 0.002);
  EXPECT_NEAR(extent->max.y(), 14.3, 0.002);
}

TEST(MapExtentTest, AFewStrayPointsOutsideDoNotMoveTheWalls) {
  std::vector<Eigen::Vector2d> points = RectanglePoints(0.0, 0.0, 20.9, 16.6, 0.01);
  const size_t strays = points.size() / 1000;  // below the 0.2 % quantile
  for (size_t i = 0; i < strays; ++i) points.emplace_back(25.0, 5.0);
  const auto extent = MeasureOuterWalls(points);
  ASSERT_TRUE(extent);
  EXPECT_NEAR(extent->size().x(), 20.9, 0.002);
}

TEST(MapExtentTest, CellsReadTheWallsWithinACell) {
  OccupancyGridOptions options;
  options.resolution = 0.05;
  OccupancyGrid grid(options);
  grid.GrowToInclude(Eigen::Vector2d(-1.0, -1.0), Eigen::Vector2d(22.0, 18.0));
  for (const Eigen::Vector2d& p : RectanglePoints(0.0, 0.0, 20.9, 16.6, 0.0)) {
    grid.SetLogOdds(grid.CellAt(p), 3.0f);
  }
  const auto extent = MeasureOuterWalls(grid, Rigid2d());
  ASSERT_TRUE(extent);
  EXPECT_NEAR(extent->size().x(), 20.9, options.resolution);
  EXPECT_NEAR(extent->size().y(), 16.6, options.resolution);
}

TEST(MapExtentTest, NothingToMeasureIsEmpty) {
  EXPECT_FALSE(MeasureOuterWalls(std::vector<Eigen::Vector2d>{}));
  EXPECT_FALSE(MeasureOuterWalls(OccupancyGrid(OccupancyGridOptions()), Rigid2d()));
}

}  // namespace
}  // namespace fleetmap

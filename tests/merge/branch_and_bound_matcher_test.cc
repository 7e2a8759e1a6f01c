#include "map_server/merge/branch_and_bound_matcher.h"

#include <gtest/gtest.h>

#include <vector>

#include "map_server/merge/score_grid.h"
#include "tests/merge/merge_test_worlds.h"

namespace fleetmap {
namespace {

// Wall points of a grid (cells above the occupied threshold), in the grid's frame.
std::vector<Eigen::Vector2d> WallPoints(const OccupancyGrid& grid, float occupied_log_odds) {
  std::vector<Eigen::Vector2d> points;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (grid.LogOdds(CellIndex(x, y)) > occupied_log_odds)
        points.push_back(grid.CellCenter(CellIndex(x, y)));
    }
  }
  return points;
}

// The peak search answers what a fresh depth-first search outside the same zones answers, one
// distinct peak after another, best first: the office's rooms offer several.
TEST(BranchAndBoundMatcherTest, PeaksComeInTheOrderRepeatedSearchesFindThem) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  const OccupancyGrid target = testing::GridFromScans(
      world, {Rigid2d(3.5, 6, 0), Rigid2d(5, 3, 0), Rigid2d(10, 6, 0), Rigid2d(10, 10, 0)},
      Rigid2d());
  const OccupancyGrid source_grid =
      testing::GridFromScans(world, {Rigid2d(10, 6, 0)}, Rigid2d(10, 6, 0.4));
  ScoreGridOptions grid_options;
  const ScoreGrid grid(target, grid_options);
  const BranchAndBoundMatcher matcher(grid, BranchAndBoundOptions());
  std::vector<Eigen::Vector2d> points = WallPoints(source_grid, grid_options.occupied_log_odds);
  ASSERT_GT(points.size(), 50u);
  if (points.size() > 300) points.resize(300);
  SearchWindow window;
  window.center = Rigid2d(
      grid.origin() + 0.5 * grid.resolution() * Eigen::Vector2d(grid.width(), grid.height()), 0.0);
  window.linear_half_extent =
      0.5 * grid.resolution() * Eigen::Vector2d(grid.width(), grid.height());
  const double min_score = 0.2;
  std::vector<ExclusionZone> zones;
  PeakSearch peaks = matcher.Peaks(points, window, min_score, zones);
  double last = 2.0;
  int found = 0;
  for (; found < 8; ++found) {
    const auto expected = matcher.Search(points, window, min_score, zones);
    const auto peak = peaks.Next();
    ASSERT_EQ(expected.has_value(), peak.has_value()) << "peak " << found;
    if (!peak) break;
    EXPECT_FLOAT_EQ(peak->score, expected->score) << "peak " << found;
    EXPECT_LE(peak->score, last);
    EXPECT_GT(peak->score, min_score);
    last = peak->score;
    zones.push_back(ExclusionZone{peak->pose, 0.5, 0.26});
    peaks.Exclude(zones.back());
  }
  EXPECT_GE(found, 3);
}

}  // namespace
}  // namespace fleetmap

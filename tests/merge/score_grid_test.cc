#include "map_server/merge/score_grid.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/merge/merge_test_worlds.h"

namespace fleetmap {
namespace {

// The office seen from one spot in its left room: walls, seen-free space, and the rest unseen.
OccupancyGrid LeftRoomSeen() {
  return testing::GridFromScans(testing::OfficeWorld(), {Rigid2d(3.5, 6, 0)}, Rigid2d());
}

TEST(ScoreGridTest, UnseenSpaceScoresZeroForMatching) {
  const ScoreGrid grid(LeftRoomSeen(), ScoreGridOptions());
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(grid.Value(-5, -5), 0.0f);
  EXPECT_EQ(grid.Value(grid.width() + 5, 0), 0.0f);
}

// Above 0, space the target did not see scores the option's value, inside its bounds and off
// them, and the pyramid's bounds still hold over every block.
TEST(ScoreGridTest, UnseenSpaceScoresTheUnknownScoreWhereSet) {
  ScoreGridOptions options;
  options.unknown_score = 0.5f;
  const ScoreGrid grid(LeftRoomSeen(), options);
  ASSERT_FALSE(grid.empty());
  // Off the grid, and inside its bounds where the scans never reached.
  EXPECT_EQ(grid.Value(-5, -5), 0.5f);
  EXPECT_EQ(grid.Value(grid.width() + 5, grid.height() + 5), 0.5f);
  int unseen = 0, free = 0;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const float v = grid.Value(x, y);
      if (!grid.Known(x, y) && v == 0.5f) ++unseen;
      if (grid.Known(x, y) && v == options.free_penalty) ++free;
    }
  }
  EXPECT_GT(unseen, 0);
  EXPECT_GT(free, 0) << "seen-free space keeps its penalty";
  const ScoreGridPyramid pyramid(grid, 4);
  for (int level = 1; level < pyramid.levels(); ++level) {
    const int block = 1 << level;
    for (int y = -block; y < grid.height(); y += 3) {
      for (int x = -block; x < grid.width(); x += 3) {
        float best = -1.0f;
        for (int dy = 0; dy < block; ++dy) {
          for (int dx = 0; dx < block; ++dx) best = std::max(best, grid.Value(x + dx, y + dy));
        }
        ASSERT_EQ(pyramid.Value(level, x, y), best)
            << "level " << level << " at " << x << ", " << y;
      }
    }
    EXPECT_EQ(pyramid.Value(level, -100, -100), 0.5f);
  }
}

}  // namespace
}  // namespace fleetmap

#include "map_server/merge/log_odds_canvas.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "map_server/merge/merge_engine.h"
#include "map_server/merge/trajectory_lookup.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// A 1 m x 1 m submap grid (5 cm) with one wall cell at (0.525, 0.025) and free elsewhere on row 0.
Submap KnownSubmap(const Rigid2d& anchor) {
  Submap s;
  s.robot_id = "a";
  s.submap_id = 0;
  s.revision = 1;
  s.finished = true;
  s.submap_in_local = anchor;
  s.grid = OccupancyGrid(OccupancyGridOptions(), Eigen::Vector2d(0, 0), 20, 20);
  for (int x = 0; x < 20; ++x) s.grid.SetLogOdds(CellIndex(x, 0), -1.0f);
  s.grid.SetLogOdds(CellIndex(10, 0), 2.0f);
  return s;
}

TEST(RenderTest, EnginePlacesKnownSubmapAtKnownPose) {
  MergeEngine engine;
  const Rigid2d anchor(1.0, 2.0, M_PI / 2);
  ASSERT_TRUE(engine.AddOrUpdateSubmap(KnownSubmap(anchor)));
  const MergeUpdate update = engine.Update();
  EXPECT_TRUE(update.graph_changed);
  ASSERT_TRUE(update.changed_region);
  const Eigen::Vector2d wall = anchor * Eigen::Vector2d(0.525, 0.025);  // = (0.975, 2.525)
  for (double resolution : {0.05, 0.1, 0.025}) {
    std::string error;
    const auto map = engine.RenderGlobalMap(Box2d{{0, 1}, {2, 4}}, resolution, &error);
    ASSERT_TRUE(map) << error;
    EXPECT_NEAR(map->LogOdds(map->CellAt(wall)), 2.0f, 1e-5) << "resolution " << resolution;
    EXPECT_LT(map->LogOdds(map->CellAt(anchor * Eigen::Vector2d(0.2, 0.025))), 0.0f);
    EXPECT_EQ(map->LogOdds(map->CellAt(anchor * Eigen::Vector2d(0.2, 0.5))), 0.0f);
  }
}

TEST(RenderTest, SubtractingASubmapRestoresTheCanvas) {
  LogOddsCanvas canvas(0.05);
  const Submap s = KnownSubmap(Rigid2d());
  canvas.AddSubmap(s.grid, Rigid2d(0.3, -0.2, 0.7), 1.0f);
  canvas.AddSubmap(s.grid, Rigid2d(0.0, 0.0, 0.0), 1.0f);
  canvas.AddSubmap(s.grid, Rigid2d(0.3, -0.2, 0.7), -1.0f);
  const OccupancyGrid grid = canvas.ToGrid(OccupancyGridOptions());
  EXPECT_NEAR(grid.LogOdds(grid.CellAt(Eigen::Vector2d(0.525, 0.025))), 2.0f, 1e-5);
  CellIndex lo, hi;
  ASSERT_TRUE(grid.KnownBounds(&lo, &hi));
  EXPECT_EQ((hi - lo).y(), 0);  // only row 0 of the unmoved copy is left
}

// Every canvas cell against the rule written out cell by cell (each canvas cell's samples
// looked up in the submap): any wall wins, else the freest value. Random submaps at random
// poses, canvases as fine as, coarser than and finer than the submap.
TEST(RenderTest, AddSubmapMatchesTheCellByCellRule) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    OccupancyGrid submap(OccupancyGridOptions(), Eigen::Vector2d(-0.4, 0.3), 23, 17);
    for (int y = 0; y < 17; ++y) {
      for (int x = 0; x < 23; ++x) {
        const double u = uniform(rng);
        if (std::abs(u) > 0.3) submap.SetLogOdds(CellIndex(x, y), static_cast<float>(2.0 * u));
      }
    }
    const Rigid2d pose(3.0 * uniform(rng), 3.0 * uniform(rng), M_PI * uniform(rng));
    const double resolution = std::array<double, 3>{0.05, 0.1, 0.03}[trial % 3];
    LogOddsCanvas canvas(resolution);
    canvas.AddSubmap(submap, pose, 1.0f);
    const OccupancyGrid grid = canvas.ToGrid(OccupancyGridOptions());
    const int samples = std::max(1, static_cast<int>(std::ceil(resolution / 0.05 - 1e-9)));
    int known = 0;
    for (int y = -5; y < grid.height() + 5; ++y) {
      for (int x = -5; x < grid.width() + 5; ++x) {
        const Eigen::Vector2d corner = grid.origin() + resolution * Eigen::Vector2d(x, y);
        float most = 0.0f, least = 0.0f;
        for (int sy = 0; sy < samples; ++sy) {
          for (int sx = 0; sx < samples; ++sx) {
            const Eigen::Vector2d p =
                corner + resolution * Eigen::Vector2d((sx + 0.5) / samples, (sy + 0.5) / samples);
            const float v = submap.LogOdds(submap.CellAt(pose.inverse() * p));
            most = std::max(most, v);
            least = std::min(least, v);
          }
        }
        const float expected = most > 0.0f ? most : least;
        known += expected != 0.0f;
        ASSERT_NEAR(grid.LogOdds(CellIndex(x, y)), expected, 1e-6)
            << "trial " << trial << " cell " << x << " " << y;
      }
    }
    EXPECT_GT(known, 100) << "trial " << trial;
  }
}

TEST(TrajectoryLookupTest, InterpolatesAndRefusesToExtrapolate) {
  const Trajectory t = {{0.0, Rigid2d(0, 0, 0)}, {1.0, Rigid2d(2, 0, 0.2)}, {10.0, Rigid2d(5, 0, 0)}};
  EXPECT_THAT(*PoseAt(t, 0.5), testing::IsNearPose(Rigid2d(1, 0, 0.1), 1e-9, 1e-9));
  EXPECT_FALSE(PoseAt(t, -1.0));
  EXPECT_FALSE(PoseAt(t, 11.0));
  EXPECT_FALSE(PoseAt(t, 5.0));  // gap of 9 s is too long to interpolate
  EXPECT_TRUE(PoseAt(t, 10.02));
}

}  // namespace
}  // namespace fleetmap

#include <unordered_set>

#include <gtest/gtest.h>

#include "robot_agent/slam/particle_filter.h"
#include "robot_agent/slam/particle_scan_matcher.h"
#include "robot_agent/slam/shared_grid_tiles.h"
#include "shared/matching/point_filter.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

testing::SegmentWorld Room() {
  testing::SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(-4.0, -3.0), Eigen::Vector2d(5.0, 3.0));
  testing::AddBox(Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.5, 1.4), &world);
  testing::AddBox(Eigen::Vector2d(-2.0, -2.0), Eigen::Vector2d(-1.7, -1.2), &world);
  return world;
}

// Rays of a scan in the robot frame, for SharedTileGrid::InsertRays.
void Rays(const LaserScan& scan, const Rigid2d& pose, std::vector<Eigen::Vector2d>* ends,
          std::vector<uint8_t>* hits) {
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!std::isfinite(scan.ranges[i])) continue;
    const double a = scan.angle(static_cast<int>(i));
    ends->push_back(pose * Eigen::Vector2d(scan.ranges[i] * std::cos(a), scan.ranges[i] * std::sin(a)));
    hits->push_back(1);
  }
}

SharedTileGrid MapOf(const testing::SegmentWorld& world, const std::vector<Rigid2d>& poses) {
  SharedTileGrid grid;
  for (const Rigid2d& pose : poses) {
    std::vector<Eigen::Vector2d> ends;
    std::vector<uint8_t> hits;
    Rays(testing::SimulateScan(world, pose, 361, -M_PI, M_PI / 180), pose, &ends, &hits);
    grid.InsertRays(pose.translation(), ends, hits);
  }
  return grid;
}

TEST(SharedTileGridTest, MarksHitsWithSubCellPositions) {
  SharedTileGrid grid;
  grid.InsertRays(Eigen::Vector2d(0.0, 0.0), {Eigen::Vector2d(1.013, 0.0)}, {1});
  Eigen::Vector2d hit;
  double d2;
  ASSERT_TRUE(grid.NearestHit(Eigen::Vector2d(1.05, 0.02), 2, &hit, &d2));
  EXPECT_NEAR(hit.x(), 1.013, 1e-4);
  EXPECT_NEAR(hit.y(), 0.0, 1e-4);
  EXPECT_FALSE(grid.NearestHit(Eigen::Vector2d(3.0, 3.0), 2, &hit, &d2));
  // Cells along the beam are free.
  const Eigen::Array2i free_cell = grid.CellOf(Eigen::Vector2d(0.5, 0.0));
  ASSERT_NE(grid.Cell(free_cell.x(), free_cell.y()), nullptr);
  EXPECT_LT(grid.Cell(free_cell.x(), free_cell.y())->log_odds, 0.0f);
}

TEST(SharedTileGridTest, CopiesShareTilesUntilWritten) {
  const testing::SegmentWorld world = Room();
  SharedTileGrid original = MapOf(world, {Rigid2d(0.0, 0.0, 0.0)});
  const size_t tiles = original.tile_count();
  ASSERT_GT(tiles, 4u);
  SharedTileGrid copy = original;
  copy.set_owner(2);
  original.set_owner(3);
  // A short beam touches one tile: only that tile is cloned.
  copy.InsertRays(Eigen::Vector2d(0.0, 0.0), {Eigen::Vector2d(0.5, 0.1)}, {1});
  std::unordered_set<const SharedTileGrid::Tile*> unique;
  original.CollectTiles(&unique);
  copy.CollectTiles(&unique);
  EXPECT_EQ(unique.size(), tiles + 1);
  // The original did not see the copy's write.
  const Eigen::Array2i cell = copy.CellOf(Eigen::Vector2d(0.5, 0.1));
  EXPECT_GT(copy.Cell(cell.x(), cell.y())->log_odds, original.Cell(cell.x(), cell.y())->log_odds);
}

TEST(ParticleMatcherTest, RecoversOffsetPose) {
  const testing::SegmentWorld world = Room();
  const SharedTileGrid grid = MapOf(world, {Rigid2d(0.0, 0.0, 0.0), Rigid2d(1.0, -1.0, 0.5)});
  const Rigid2d truth(0.4, -0.3, 0.2);
  const LaserScan scan = testing::SimulateScan(world, truth, 361, -M_PI, M_PI / 180);
  const std::vector<Eigen::Vector2f> points = VoxelFilter(ToPointsInRobotFrame(scan), 0.1f);
  for (const Rigid2d& guess : {Rigid2d(0.5, -0.2, 0.25), Rigid2d(0.3, -0.4, 0.15), Rigid2d(0.45, -0.3, 0.2)}) {
    const ParticleMatch match = MatchAgainstTiles(points, grid, guess, ParticleMatcherOptions());
    EXPECT_TRUE(match.good);
    EXPECT_THAT(match.pose, IsNearPose(truth, 0.01, 0.005));
    EXPECT_GT(match.inlier_fraction, 0.9);
  }
  const ParticleMatcherOptions options;
  EXPECT_GT(ScanLogLikelihood(points, grid, truth, options),
            ScanLogLikelihood(points, grid, Rigid2d(0.45, -0.3, 0.2), options));
}

TEST(ParticleFilterTest, EffectiveSampleSize) {
  EXPECT_NEAR(ParticleFilter::EffectiveSampleSize({-1.0, -1.0, -1.0, -1.0}), 4.0, 1e-12);
  EXPECT_NEAR(ParticleFilter::EffectiveSampleSize({0.0, -1e3, -1e3, -1e3}), 1.0, 1e-9);
  EXPECT_NEAR(ParticleFilter::EffectiveSampleSize({std::log(0.5), std::log(0.5), -1e3}), 2.0, 1e-9);
}

}  // namespace
}  // namespace fleetmap

#include "shared/core/likelihood_field.h"

#include <random>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

// Few obstacles take the disk-stamping path, many the full distance transform: both exact.
TEST(LikelihoodFieldTest, DistancesMatchBruteForce) {
  for (int count : {12, 600}) {
    OccupancyGridOptions options;
    options.resolution = 0.1;
    OccupancyGrid grid(options, Eigen::Vector2d(0, 0), 60, 40);
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> ux(0, 59), uy(0, 39);
    std::vector<CellIndex> obstacles;
    for (int i = 0; i < count; ++i) {
      obstacles.emplace_back(ux(rng), uy(rng));
      grid.SetLogOdds(obstacles.back(), 3.0f);
    }
    LikelihoodFieldOptions field_options;
    field_options.max_distance = 1.5;
    const LikelihoodField field(grid, field_options);
    for (int y = -5; y < 45; ++y) {
      for (int x = -5; x < 65; ++x) {
        double best = 1e9;
        for (const CellIndex& o : obstacles) best = std::min(best, std::hypot(x - o.x(), y - o.y()) * 0.1);
        best = std::min(best, 1.5);
        const Eigen::Vector2d centre = grid.CellCenter(CellIndex(x, y));
        ASSERT_NEAR(field.Distance(centre), best, 1e-4) << count << " obstacles, cell " << x << "," << y;
      }
    }
  }
}

TEST(LikelihoodFieldTest, WallDistanceAndGradientPointAway) {
  // A vertical wall at x = 1.0 built from points.
  std::vector<Eigen::Vector2d> wall;
  for (double y = -2.0; y <= 2.0; y += 0.01) wall.emplace_back(1.0, y);
  LikelihoodFieldOptions options;
  options.max_distance = 1.0;
  const LikelihoodField field(wall, 0.05, options);
  Eigen::Vector2d gradient;
  const double d = field.DistanceAndGradient({0.6, 0.0}, &gradient);
  EXPECT_NEAR(d, 0.4, 0.05);
  EXPECT_LT(gradient.x(), -0.8);  // moving towards the wall shrinks the distance
  EXPECT_NEAR(gradient.y(), 0.0, 0.05);
  EXPECT_NEAR(field.Distance({1.02, 0.5}), 0.0, 0.05);
  EXPECT_DOUBLE_EQ(field.Distance({50.0, 0.0}), 1.0);  // outside the field
}

TEST(LikelihoodFieldTest, EmptyMapIsFarEverywhere) {
  OccupancyGrid grid(OccupancyGridOptions(), Eigen::Vector2d(0, 0), 10, 10);
  const LikelihoodField field(grid, LikelihoodFieldOptions());
  EXPECT_FALSE(field.has_obstacles());
  EXPECT_DOUBLE_EQ(field.Distance({0.2, 0.2}), 1.0);
}

}  // namespace
}  // namespace fleetmap

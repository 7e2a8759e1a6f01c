#include "shared/matching/match_grid.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "shared/core/likelihood_field.h"
#include "shared/matching/match_grid_pyramid.h"

namespace fleetmap {
namespace {

TEST(MatchGridTest, EmptyGridReadsMaxDistanceEverywhere) {
  MatchGrid grid;
  EXPECT_TRUE(grid.empty());
  EXPECT_NEAR(grid.Distance(Eigen::Vector2d(1.0, 2.0)), grid.max_distance(), 1e-6);
  Eigen::Vector2d gradient;
  EXPECT_NEAR(grid.SquaredDistance(Eigen::Vector2d(NAN, 0.0), &gradient), grid.max_squared_distance(), 1e-6);
  EXPECT_EQ(gradient, Eigen::Vector2d::Zero());
}

TEST(MatchGridTest, DistancesAreExactToThePointsAtCellCentres) {
  MatchGridOptions options;
  options.resolution = 0.05;
  options.max_distance = 0.5;
  MatchGrid grid(options);
  const Eigen::Vector2d point(1.013, -0.321);
  grid.AddPoint(point);
  ASSERT_FALSE(grid.empty());
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d centre =
          grid.origin() + options.resolution * Eigen::Vector2d(x + 0.5, y + 0.5);
      const double expected = std::min(options.max_distance, (centre - point).norm());
      ASSERT_NEAR(grid.CellSquaredDistance(x, y), expected * expected, 1e-5) << x << " " << y;
    }
  }
}

// Near a straight wall the squared distance is a quadratic, which the bicubic interpolation
// reproduces: zero exactly on the wall wherever it sits relative to the cells, with curvature 2
// across it. (Wall points sit at cell-centre x so that "one point per cell" keeps them exact.)
TEST(MatchGridTest, InterpolationIsExactNearAStraightWall) {
  for (double wall_y : {1.0, 1.0125, 1.025, 1.04}) {
    std::vector<Eigen::Vector2d> points;
    for (int i = -40; i <= 40; ++i) points.emplace_back(0.025 + 0.05 * i, wall_y);
    const MatchGrid grid = MatchGrid::FromPoints(points, MatchGridOptions());
    for (double offset : {-0.07, -0.031, 0.0, 0.013, 0.06}) {
      Eigen::Vector2d gradient;
      Eigen::Matrix2d hessian;
      const double f = grid.SquaredDistance(Eigen::Vector2d(0.123, wall_y + offset), &gradient, &hessian);
      EXPECT_NEAR(f, offset * offset, 2e-5) << wall_y << " " << offset;
      EXPECT_NEAR(gradient.y(), 2.0 * offset, 2e-3);
      EXPECT_NEAR(hessian(1, 1), 2.0, 0.05);
      EXPECT_NEAR(hessian(0, 0), 0.0, 0.05);
    }
  }
}

// The ripple that trapped the scan matcher: with one stored point per cell the squared distance
// just off a wall rises by (s/2)^2 between two points s apart. Wall pieces remove it, for
// dense and for sparse sampling at any phase against the cells.
TEST(MatchGridTest, NoRippleAlongASampledWall) {
  for (double spacing : {0.02, 0.05, 0.14}) {
    std::vector<Eigen::Vector2d> points;
    for (int i = -30; i <= 30; ++i) points.emplace_back(0.013 + spacing * i, 0.517);
    const MatchGrid grid = MatchGrid::FromPoints(points, MatchGridOptions());
    MatchGridOptions point_options;
    point_options.surface.radius = 0.0;
    const MatchGrid point_grid = MatchGrid::FromPoints(points, point_options);
    double lo = 1e9, hi = -1e9, point_lo = 1e9, point_hi = -1e9;
    for (double x = -0.5; x <= 0.5; x += 0.002) {
      const Eigen::Vector2d p(x, 0.517 + 0.03);
      lo = std::min(lo, grid.SquaredDistance(p));
      hi = std::max(hi, grid.SquaredDistance(p));
      point_lo = std::min(point_lo, point_grid.SquaredDistance(p));
      point_hi = std::max(point_hi, point_grid.SquaredDistance(p));
    }
    EXPECT_NEAR(lo, 0.03 * 0.03, 2e-5) << spacing;
    EXPECT_LT(hi - lo, 4e-5) << spacing;
    // The point field really has the ripple where the samples are sparser than the cells (so
    // this test can tell the two apart); sampled once per cell it is hidden between centres.
    if (spacing > 0.1) {
      EXPECT_GT(point_hi - point_lo, 1e-3) << spacing;
    }
  }
}

// A wall piece reaches only as far as its points: the field past a wall's end is the distance
// to the end, as for points.
TEST(MatchGridTest, WallPiecesStopAtTheWallsEnd) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 20; ++i) points.emplace_back(0.02 * i, 0.0);
  const MatchGrid grid = MatchGrid::FromPoints(points, MatchGridOptions());
  EXPECT_NEAR(grid.Distance(Eigen::Vector2d(0.4 + 0.1, 0.0)), 0.1, 0.01);
  EXPECT_NEAR(grid.Distance(Eigen::Vector2d(-0.1, 0.0)), 0.1, 0.01);
}

// With observed cells tracked, the search score tells seen free space (0: no wall can be there)
// from space no scan saw (unknown_score), and keeps the distance score near walls.
TEST(MatchGridTest, TrackedGridScoresUnseenCellsAsUnknown) {
  MatchGridOptions options;
  options.track_observed = true;
  MatchGrid grid(options);
  std::vector<Eigen::Vector2f> wall;  // a wall 3 m ahead of a robot at the origin
  for (int i = -20; i <= 20; ++i) wall.emplace_back(3.0f, 0.05f * static_cast<float>(i));
  grid.AddPoints(wall, Rigid2d());
  auto cell_of = [&](double x, double y) {
    return Eigen::Array2i(static_cast<int>(std::floor((x - grid.origin().x()) / grid.resolution())),
                          static_cast<int>(std::floor((y - grid.origin().y()) / grid.resolution())));
  };
  const Eigen::Array2i free_cell = cell_of(1.5, 0.0), wall_cell = cell_of(3.0, 0.3);
  const Eigen::Array2i behind = cell_of(3.8, 0.0), beside = cell_of(1.5, 2.0);
  EXPECT_TRUE(grid.Observed(Eigen::Vector2d(1.5, 0.0)));
  EXPECT_FLOAT_EQ(grid.CellScore(free_cell.x(), free_cell.y()), 0.0f);
  EXPECT_GT(grid.CellScore(wall_cell.x(), wall_cell.y()), 0.9f);
  EXPECT_FALSE(grid.Observed(Eigen::Vector2d(3.8, 0.0)));
  EXPECT_FLOAT_EQ(grid.CellScore(behind.x(), behind.y()), options.unknown_score);
  EXPECT_FLOAT_EQ(grid.CellScore(beside.x(), beside.y()), options.unknown_score);
  // Untracked grids score seen and unseen space alike.
  const MatchGrid plain = MatchGrid::FromPoints({Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(3.0, 0.05),
                                                 Eigen::Vector2d(3.0, 0.1)}, MatchGridOptions());
  const Eigen::Vector2d g = (Eigen::Vector2d(1.5, 0.0) - plain.origin()) / plain.resolution();
  EXPECT_TRUE(plain.Observed(Eigen::Vector2d(1.5, 0.0)));
  EXPECT_FLOAT_EQ(plain.CellScore(static_cast<int>(g.x()), static_cast<int>(g.y())), 0.0f);
}

// Seen free means inside the space rays crossed: a spot next to a wall that rays grazed on their
// way further along it is not, however many rays passed.
TEST(MatchGridTest, SeenFreeIsTheInteriorOfCrossedSpace) {
  MatchGridOptions options;
  options.track_observed = true;
  MatchGrid grid(options);
  // A robot at the origin, a wall 1 m to its right seen far ahead at shallow angles, and beams
  // straight ahead that saw nothing within 8 m.
  std::vector<Eigen::Vector2f> wall;
  for (double angle = -0.24; angle < -0.12; angle += 0.0175) {
    wall.emplace_back(static_cast<float>(-1.0 / std::tan(angle)), -1.0f);
  }
  std::vector<Eigen::Vector2f> nothing;
  for (int degree = -10; degree <= 10; ++degree) {
    const double angle = degree * M_PI / 180.0;
    nothing.emplace_back(static_cast<float>(8.0 * std::cos(angle)), static_cast<float>(8.0 * std::sin(angle)));
  }
  grid.AddPoints(wall, nothing, Rigid2d());
  EXPECT_TRUE(grid.SeenFree(Eigen::Vector2d(2.0, 0.02), 0.08));    // mid-corridor, crossed
  EXPECT_FALSE(grid.SeenFree(Eigen::Vector2d(5.0, -0.99), 0.08));  // on the wall, grazed
  EXPECT_FALSE(grid.SeenFree(Eigen::Vector2d(5.0, -1.3), 0.08));   // behind it
  EXPECT_FALSE(grid.SeenFree(Eigen::Vector2d(-1.0, 0.0), 0.08));   // behind the robot
  EXPECT_FALSE(MatchGrid().SeenFree(Eigen::Vector2d(3.0, 0.0), 0.08));  // not tracked
}

// Seen space in 2 x 2 blocks of 2.5 cm cells is a 5 cm grid's, point for point: the rays of a
// 1-degree fan leave 2.5 cm cells between them unseen from about 1.5 m on, but not 5 cm ones.
TEST(MatchGridTest, SeenSpaceInBlocksIsACoarserGridsSeenSpace) {
  std::vector<Eigen::Vector2f> wall;  // 2.5 m ahead
  for (int degree = -30; degree <= 30; ++degree) {
    wall.emplace_back(2.5f, static_cast<float>(2.5 * std::tan(degree * M_PI / 180.0)));
  }
  MatchGridOptions coarse;
  coarse.track_observed = true;
  MatchGridOptions fine = coarse;
  fine.resolution = 0.025;
  MatchGridOptions blocks = fine;
  blocks.observed_block = 2;
  MatchGrid coarse_grid(coarse), fine_grid(fine), block_grid(blocks);
  for (MatchGrid* grid : {&coarse_grid, &fine_grid, &block_grid}) grid->AddPoints(wall, Rigid2d());
  int coarse_free = 0, fine_free = 0, disagree = 0;
  // Farther than max_distance from the wall, so the clearance test passes in every grid alike.
  for (double x = 1.0; x <= 2.15; x += 0.0073) {
    for (double y = -0.4; y <= 0.4; y += 0.0073) {
      const Eigen::Vector2d p(x, y);
      const bool seen_free = coarse_grid.SeenFree(p, 0.08);
      coarse_free += seen_free;
      fine_free += fine_grid.SeenFree(p, 0.08);
      disagree += block_grid.SeenFree(p, 0.08) != seen_free;
    }
  }
  EXPECT_GT(coarse_free, 10000);
  EXPECT_LT(fine_free, coarse_free * 9 / 10);
  EXPECT_EQ(disagree, 0);
}

// A scan prepared once goes into grids that already hold different scans (so have different
// extents) as AddPoints would put it; seen space in blocks survives the growth it causes.
TEST(MatchGridTest, APreparedScanGoesIntoEveryGridAsAddPointsPutsIt) {
  MatchGridOptions options = MatchGridOptions();
  options.resolution = 0.025;
  options.track_observed = true;
  options.observed_block = 2;
  std::vector<Eigen::Vector2f> room;  // a 4 x 3 m room seen from its centre
  for (int degree = 0; degree < 360; degree += 2) {
    const double a = degree * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
    const double range =
        std::min(2.0 / std::max(std::abs(c), 1e-9), 1.5 / std::max(std::abs(s), 1e-9));
    room.emplace_back(static_cast<float>(range * c), static_cast<float>(range * s));
  }
  const std::vector<Eigen::Vector2f> far_ends = {Eigen::Vector2f(6.0f, 0.5f)};
  const Rigid2d first(0.0, 0.0, 0.0), second(-5.0, -4.0, 0.7);  // grows down and left
  MatchGrid direct(options), prepared(options), fresh(options);
  direct.AddPoints(room, first);
  prepared.AddPoints(room, first);
  const MatchGrid before_growth = direct;
  direct.AddPoints(room, far_ends, second);
  const MatchGridBatch batch = prepared.PrepareScan(room, far_ends, second);
  prepared.Add(batch);
  fresh.Add(batch);
  ASSERT_EQ(direct.width(), prepared.width());
  ASSERT_EQ(direct.height(), prepared.height());
  EXPECT_NE(direct.width(), fresh.width());
  EXPECT_EQ(direct.squared_distances(), prepared.squared_distances());
  int seen = 0, seen_before = 0, differ = 0, fresh_differ = 0, moved = 0;
  for (double x = -12.0; x <= 3.0; x += 0.013) {
    for (double y = -8.0; y <= 3.0; y += 0.013) {
      const Eigen::Vector2d p(x, y);
      seen += direct.Observed(p);
      differ += direct.Observed(p) != prepared.Observed(p) ||
                direct.SeenFree(p, 0.08) != prepared.SeenFree(p, 0.08);
      // The fresh grid holds the second scan only; inside that room it reads as the others.
      // The first room's seen space stays where it was when the grid grew.
      seen_before += before_growth.Observed(p);
      moved += before_growth.Observed(p) && !direct.Observed(p);
      const Eigen::Vector2d in_second = second.inverse() * p;
      if (std::abs(in_second.x()) < 1.9 && std::abs(in_second.y()) < 1.4) {
        // Up to rounding: the grids' origins differ.
        fresh_differ += std::abs(direct.SquaredDistance(p) - fresh.SquaredDistance(p)) > 1e-7 ||
                        direct.Observed(p) != fresh.Observed(p);
      }
    }
  }
  EXPECT_GT(seen, 100000);
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(fresh_differ, 0);
  EXPECT_GT(seen_before, 20000);
  EXPECT_EQ(moved, 0);
  EXPECT_LT(before_growth.width(), direct.width());
}

TEST(MatchGridTest, GrowingKeepsEarlierPoints) {
  MatchGrid grid;
  grid.AddPoint(Eigen::Vector2d(0.0, 0.0));
  grid.AddPoint(Eigen::Vector2d(40.0, -30.0));  // forces a large growth
  EXPECT_EQ(grid.obstacle_count(), 2);
  EXPECT_LT(grid.Distance(Eigen::Vector2d(0.0, 0.0)), 0.04);
  EXPECT_LT(grid.Distance(Eigen::Vector2d(40.0, -30.0)), 0.04);
  EXPECT_NEAR(grid.Distance(Eigen::Vector2d(0.1, 0.0)), 0.1, 0.03);
}

TEST(MatchGridTest, AbsurdPointsAreIgnoredNotAllocated) {
  MatchGrid grid;
  grid.AddPoint(Eigen::Vector2d(0.0, 0.0));
  grid.AddPoint(Eigen::Vector2d(1e12, 1e12));
  grid.AddPoint(Eigen::Vector2d(INFINITY, 0.0));
  EXPECT_EQ(grid.obstacle_count(), 1);
  EXPECT_LT(grid.width(), 1000);
}

TEST(MatchGridTest, AgreesWithTheCoreLikelihoodField) {
  std::vector<Eigen::Vector2d> points;
  for (double x = 0.0; x <= 3.0; x += 0.05) points.emplace_back(x + 0.025, 1.025);
  LikelihoodFieldOptions field_options;
  field_options.max_distance = 0.4;
  const LikelihoodField field(points, 0.05, field_options);
  const MatchGrid from_field = MatchGrid::FromLikelihoodField(field, 0.4);
  MatchGridOptions options;
  options.max_distance = 0.4;
  const MatchGrid from_points = MatchGrid::FromPoints(points, options);
  for (double x = 0.2; x < 2.8; x += 0.13) {
    for (double y = 0.7; y < 1.3; y += 0.07) {
      const Eigen::Vector2d p(x, y);
      EXPECT_NEAR(from_field.Distance(p), from_points.Distance(p), 0.01) << p.transpose();
    }
  }
}

TEST(MatchGridPyramidTest, EveryLevelBoundsItsBlock) {
  MatchGridOptions options;
  options.max_distance = 0.3;
  MatchGrid grid(options);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
  for (int i = 0; i < 40; ++i) grid.AddPoint(Eigen::Vector2d(coord(rng), coord(rng)));
  const MatchGridPyramid pyramid(grid, 5);
  ASSERT_EQ(pyramid.levels(), 5);
  const MatchGridPyramid base_only(grid, 1);
  for (int level = 0; level < 5; ++level) {
    const int k = 1 << level;
    for (int y = -k; y < grid.height(); y += 3) {
      for (int x = -k; x < grid.width(); x += 3) {
        int best = 0;
        for (int by = y; by < y + k; ++by) {
          for (int bx = x; bx < x + k; ++bx) best = std::max(best, base_only.BlockScore(0, bx, by));
        }
        ASSERT_EQ(pyramid.BlockScore(level, x, y), best) << level << " " << x << " " << y;
      }
    }
  }
}

}  // namespace
}  // namespace fleetmap

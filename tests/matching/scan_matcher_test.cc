#include "shared/matching/scan_matcher.h"

#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "shared/matching/point_filter.h"
#include "tests/matching/matching_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

constexpr double kDegree = M_PI / 180.0;

ScanMatcherOptions WideOptions() {
  ScanMatcherOptions options;
  options.search.linear_window = 0.4;
  options.search.angular_window = 12.0 * kDegree;
  // The prior must not pull a good match: the guess is deliberately far off here.
  options.refinement.prior_translation_sigma = 0.0;
  options.refinement.prior_rotation_sigma = 0.0;
  return options;
}

class ScanMatcherTest : public ::testing::TestWithParam<Rigid2d> {
 protected:
  const testing::SegmentWorld world_ = testing::FurnishedRoom();
  const MatchGrid grid_ = testing::WorldGrid(world_);
};

TEST_P(ScanMatcherTest, RecoversKnownOffsetWithBranchAndBound) {
  for (const Rigid2d& truth : {Rigid2d(0.4, -0.7, 0.3), Rigid2d(-2.0, 1.5, -2.0), Rigid2d(3.0, 2.0, 2.6)}) {
    const std::vector<Eigen::Vector2f> points = ToPointsInRobotFrame(testing::SimulateScan(world_, truth));
    const Rigid2d guess = truth * GetParam();
    const MatchGridPyramid pyramid(grid_);
    const auto match = MatchScan(points, grid_, &pyramid, guess, guess, WideOptions());
    ASSERT_TRUE(match.has_value()) << truth;
    EXPECT_THAT(match->pose, IsNearPose(truth, 0.01, 0.2 * kDegree)) << truth;
    EXPECT_GT(match->score, 0.8);
    EXPECT_GT(match->inlier_fraction, 0.95);
  }
}

TEST_P(ScanMatcherTest, RecoversKnownOffsetWithBruteForce) {
  const Rigid2d truth(0.4, -0.7, 0.3);
  const std::vector<Eigen::Vector2f> points =
      VoxelFilter(ToPointsInRobotFrame(testing::SimulateScan(world_, truth)), 0.1f);
  const Rigid2d guess = truth * GetParam();
  const auto match = MatchScan(points, grid_, nullptr, guess, guess, WideOptions());
  ASSERT_TRUE(match.has_value());
  EXPECT_THAT(match->pose, IsNearPose(truth, 0.01, 0.2 * kDegree));
}

INSTANTIATE_TEST_SUITE_P(Guesses, ScanMatcherTest,
                         ::testing::Values(Rigid2d(0.3, 0.0, 0.0), Rigid2d(-0.3, 0.3, 0.0),
                                           Rigid2d(0.0, 0.0, 10.0 * kDegree),
                                           Rigid2d(0.3, -0.3, -10.0 * kDegree),
                                           Rigid2d(-0.3, -0.3, 10.0 * kDegree),
                                           Rigid2d(0.0, 0.0, 0.0)));

TEST(ScanMatcherRefinementTest, RefinementAloneConvergesFromAFewCentimetres) {
  const testing::SegmentWorld world = testing::FurnishedRoom();
  const MatchGrid grid = testing::WorldGrid(world);
  const Rigid2d truth(-1.0, 0.5, 1.0);
  const std::vector<Eigen::Vector2f> points = ToPointsInRobotFrame(testing::SimulateScan(world, truth));
  ScanMatcherOptions options;
  options.use_correlative_search = false;
  const Rigid2d guess = truth * Rigid2d(0.08, -0.06, 2.0 * kDegree);
  const auto match = MatchScan(points, grid, nullptr, guess, truth, options);
  ASSERT_TRUE(match.has_value());
  EXPECT_THAT(match->pose, IsNearPose(truth, 0.01, 0.2 * kDegree));
}

// The local SLAM case: the map holds the previous scan, and the robot moved a few centimetres.
// Most of the new scan's beams hit the walls next to where the previous scan's did; a field of
// sampled points has its minimum at "not moved" (the beams on the same spots), a field of wall
// pieces at the true move. Refinement only, from the odometry prediction.
TEST(ScanMatcherRefinementTest, FollowsASmallMoveAgainstThePreviousScan) {
  const testing::SegmentWorld world = testing::FurnishedRoom();
  const Rigid2d before(-1.0, 0.5, 0.3);
  MatchGridOptions grid_options;
  MatchGrid grid(grid_options);
  grid.AddPoints(ToPointsInRobotFrame(testing::SimulateScan(world, before)), before);
  ScanMatcherOptions options;
  options.use_correlative_search = false;
  options.refinement.prior_translation_sigma = 0.2;
  options.refinement.prior_rotation_sigma = 0.1;
  for (const Rigid2d& move : {Rigid2d(0.03, 0.0, 0.0), Rigid2d(0.05, 0.01, 0.01), Rigid2d(0.0, -0.04, 0.0)}) {
    const Rigid2d truth = before * move;
    const std::vector<Eigen::Vector2f> points =
        VoxelFilter(ToPointsInRobotFrame(testing::SimulateScan(world, truth)), 0.05f);
    const Rigid2d predicted = truth * Rigid2d(0.01, -0.01, 0.005);
    const auto match = MatchScan(points, grid, nullptr, predicted, predicted, options);
    ASSERT_TRUE(match.has_value());
    EXPECT_THAT(match->pose, IsNearPose(truth, 0.005, 0.1 * kDegree)) << move;
  }
}

// Two exact scans of a room, 0.1 m apart with an 8 m laser: far down the side wall the first
// scan's returns are 0.3-0.7 m apart and the second scan's beams hit it exactly 0.1 m further
// on. Without joining consecutive returns each return's nearest map point was its own beam's
// previous hit, and the match came out 5 cm short.
TEST(ScanMatcherRefinementTest, TwoExactScansOfARoomMatchAtTheirMove) {
  testing::SegmentWorld room = testing::BoxWorld(Eigen::Vector2d(-1.0, -1.0), Eigen::Vector2d(11.0, 7.0));
  testing::AddBox(Eigen::Vector2d(2.0, 2.0), Eigen::Vector2d(3.0, 2.5), &room);
  testing::AddBox(Eigen::Vector2d(6.0, 3.5), Eigen::Vector2d(6.5, 5.0), &room);
  MatchGrid grid;
  grid.AddPoints(ToPointsInRobotFrame(testing::SimulateScan(room, Rigid2d())), Rigid2d());
  const Rigid2d truth(0.1, 0.0, 0.0);
  LaserScan scan = testing::SimulateScan(room, truth);
  for (float& range : scan.ranges) {
    if (!(range < 7.0f)) range = LaserScan::kNoReturn;  // as local SLAM matches: inside the horizon
  }
  ScanMatcherOptions options;
  options.use_correlative_search = false;
  options.refinement.prior_translation_sigma = 0.2;
  options.refinement.prior_rotation_sigma = 0.1;
  const auto match = MatchScan(VoxelFilter(ToPointsInRobotFrame(scan), 0.05f), grid, nullptr, truth, truth, options);
  ASSERT_TRUE(match.has_value());
  EXPECT_THAT(match->pose, IsNearPose(truth, 0.01, 0.05 * kDegree));
}

// Two long parallel walls and nothing else: the scan fixes y and theta but says nothing about x.
TEST(ScanMatcherCorridorTest, FeaturelessCorridorKeepsThePriorAlongItsAxis) {
  testing::SegmentWorld corridor = {{Eigen::Vector2d(-50.0, -1.0), Eigen::Vector2d(50.0, -1.0)},
                                    {Eigen::Vector2d(-50.0, 1.0), Eigen::Vector2d(50.0, 1.0)}};
  const MatchGrid grid = testing::WorldGrid(corridor);
  const Rigid2d truth(0.0, 0.2, 0.05);
  const std::vector<Eigen::Vector2f> points = ToPointsInRobotFrame(testing::SimulateScan(corridor, truth));
  // Odometry says we are 0.25 m further along; the scan cannot contradict it.
  const Rigid2d odometry(0.25, 0.3, 0.1);
  ScanMatcherOptions options;
  options.search.linear_window = 0.3;
  options.search.angular_window = 0.1;
  const auto match = MatchScan(points, grid, nullptr, odometry, odometry, options);
  ASSERT_TRUE(match.has_value());
  EXPECT_NEAR(match->pose.x(), odometry.x(), 0.03);  // stays put along the axis
  EXPECT_NEAR(match->pose.y(), truth.y(), 0.01);     // corrected across it
  EXPECT_NEAR(match->pose.rotation(), truth.rotation(), 0.2 * kDegree);
  // Low confidence along the axis: the variance there is dominated by the prior, orders of
  // magnitude above the variance across the corridor.
  EXPECT_GT(match->covariance(0, 0), 100.0 * match->covariance(1, 1));
  EXPECT_NEAR(std::sqrt(match->covariance(0, 0)), options.refinement.prior_translation_sigma, 0.05);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> info(match->scan_information);
  EXPECT_LT(info.eigenvalues()(0), 1e-3 * info.eigenvalues()(2));
}

// A box the map has not seen yet (it came into view with this scan): under the wide loss its
// returns, 0.2 m from the nearest mapped wall, still pull the refinement round; the narrow
// second pass leaves them out.
TEST(ScanMatcherRefinementTest, ANarrowSecondPassIgnoresASurfaceTheMapHasNotSeen) {
  testing::SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(-5.0, -4.0), Eigen::Vector2d(5.0, 4.0));
  const MatchGrid map = testing::WorldGrid(world);
  // Unmapped: a cabinet 0.2 m in front of the east wall.
  testing::AddBox(Eigen::Vector2d(4.8, 0.2), Eigen::Vector2d(4.9, 2.6), &world);
  const Rigid2d truth(-1.0, -0.5, 0.2);
  const std::vector<Eigen::Vector2f> points = ToPointsInRobotFrame(testing::SimulateScan(world, truth));
  ScanMatcherOptions options;
  options.use_correlative_search = false;
  const auto wide = MatchScan(points, map, nullptr, truth, truth, options);
  options.refinement.fine_robust_scale = 0.02;
  const auto narrow = MatchScan(points, map, nullptr, truth, truth, options);
  ASSERT_TRUE(wide && narrow);
  const double wide_error = std::abs(NormalizeAngle(wide->pose.rotation() - truth.rotation()));
  const double narrow_error = std::abs(NormalizeAngle(narrow->pose.rotation() - truth.rotation()));
  EXPECT_GT(wide_error, 0.2 * kDegree);  // the case this test is about (0.36 deg, 4 cm)
  EXPECT_LT(narrow_error, 0.25 * wide_error);
  EXPECT_THAT(narrow->pose, IsNearPose(truth, 0.005, 0.05 * kDegree));
}

TEST(ScanMatcherBadInputTest, NoPointsOrEmptyGridGiveNoMatch) {
  const MatchGrid grid = testing::WorldGrid(testing::FurnishedRoom());
  ScanMatcherOptions options;
  EXPECT_FALSE(MatchScan({}, grid, nullptr, Rigid2d(), Rigid2d(), options));
  EXPECT_FALSE(MatchScan({Eigen::Vector2f(1.0f, 1.0f)}, MatchGrid(), nullptr, Rigid2d(), Rigid2d(), options));
  EXPECT_FALSE(MatchScan({Eigen::Vector2f(1.0f, 1.0f)}, grid, nullptr, Rigid2d(INFINITY, 0, 0), Rigid2d(), options));
}

TEST(PointFilterTest, VoxelFilterKeepsOnePointPerCell) {
  const std::vector<Eigen::Vector2f> points = {{0.01f, 0.01f}, {0.02f, 0.03f}, {0.2f, 0.0f},
                                               {-0.01f, 0.0f}, {NAN, 0.0f}};
  const std::vector<Eigen::Vector2f> kept = VoxelFilter(points, 0.1f);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[0], points[0]);
  EXPECT_EQ(kept[1], points[2]);
  EXPECT_EQ(kept[2], points[3]);
  EXPECT_EQ(RangeFilter(points, 0.1f).size(), 3u);
}

TEST(PointFilterTest, ThinBeamsKeepsEveryKthNearBeamAndEveryFarOne) {
  // 1 degree apart: at 0.5 m returns are 8.7 mm apart (every 5th beam for 5 cm), at 1 m 17 mm
  // (every 2nd), at 5 m 87 mm (all).
  std::vector<float> ranges(30, 0.5f);
  for (int i = 10; i < 20; ++i) ranges[static_cast<size_t>(i)] = 1.0f;
  for (int i = 20; i < 30; ++i) ranges[static_cast<size_t>(i)] = 5.0f;
  ranges[12] = LaserScan::kNoReturn;
  const LaserScan scan = MakeLaserScan(0.0, 0.0f, static_cast<float>(M_PI / 180), 0.02f, 8.0f, ranges);
  const LaserScan thinned = ThinBeams(scan, 0.05f);
  std::vector<int> kept;
  for (int i = 0; i < thinned.size(); ++i) {
    if (thinned.IsReturn(i)) kept.push_back(i);
  }
  const std::vector<int> expected = {0, 5, 10, 14, 16, 18, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29};
  EXPECT_EQ(kept, expected);
  EXPECT_EQ(ThinBeams(scan, 0.0f).ranges, scan.ranges);
}

// Which beams survive must not depend on the range noise: a filter that picks returns by their
// measured positions picks the ones noise pushed one way, and the match of the survivors turns.
TEST(PointFilterTest, ThinBeamsPicksTheSameBeamsWhateverTheNoise) {
  const testing::SegmentWorld corridor = {{Eigen::Vector2d(-5.0, -0.8), Eigen::Vector2d(20.0, -0.8)},
                                          {Eigen::Vector2d(-5.0, 1.6), Eigen::Vector2d(20.0, 1.6)}};
  const LaserScan exact = testing::SimulateScan(corridor, Rigid2d());
  LaserScan noisy = exact;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  for (float& range : noisy.ranges) range += noise(rng);
  const LaserScan thinned_exact = ThinBeams(exact, 0.05f), thinned_noisy = ThinBeams(noisy, 0.05f);
  int kept = 0, differ = 0;
  for (int i = 0; i < exact.size(); ++i) {
    kept += thinned_exact.IsReturn(i) ? 1 : 0;
    differ += thinned_exact.IsReturn(i) != thinned_noisy.IsReturn(i) ? 1 : 0;
  }
  EXPECT_LT(kept, exact.size() * 3 / 4);  // it does thin
  EXPECT_LE(differ, 2);                   // only beams at a stride boundary may change
}

}  // namespace
}  // namespace fleetmap

#include "shared/matching/correlative_search.h"

#include <gtest/gtest.h>

#include "tests/matching/matching_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

class CorrelativeSearchTest : public ::testing::TestWithParam<Rigid2d> {
 protected:
  const testing::SegmentWorld world_ = testing::FurnishedRoom();
  const MatchGrid grid_ = testing::WorldGrid(world_);
  const Rigid2d truth_{0.4, -0.7, 0.3};
  const std::vector<Eigen::Vector2f> points_ =
      ToPointsInRobotFrame(testing::SimulateScan(world_, truth_));
};

TEST_P(CorrelativeSearchTest, BranchAndBoundFindsTheTrueCell) {
  const Rigid2d guess = truth_ * GetParam();
  const MatchGridPyramid pyramid(grid_, 6);
  CorrelativeSearchOptions options;
  options.linear_window = 0.5;
  options.angular_window = 0.25;
  const auto match = SearchBranchAndBound(points_, pyramid, guess, options);
  ASSERT_TRUE(match.has_value());
  // Within one cell and one angular step (about 0.4 degrees for 8 m ranges).
  EXPECT_THAT(match->pose, IsNearPose(truth_, 0.05 * 1.5, 0.012));
  EXPECT_GT(match->score, 0.7);
}

TEST_P(CorrelativeSearchTest, BruteForceAgreesWithBranchAndBound) {
  const Rigid2d guess = truth_ * GetParam();
  CorrelativeSearchOptions options;
  options.linear_window = 0.5;
  options.angular_window = 0.25;
  options.angular_step = 0.01;
  options.translation_penalty = 0.0;
  options.rotation_penalty = 0.0;
  const auto brute = SearchBruteForce(points_, grid_, guess, options);
  const auto bnb = SearchBranchAndBound(points_, MatchGridPyramid(grid_, 5), guess, options);
  ASSERT_TRUE(brute && bnb);
  EXPECT_THAT(brute->pose, IsNearPose(truth_, 0.075, 0.012));
  // Same candidate set, exact search: the scores agree up to byte quantisation.
  EXPECT_NEAR(brute->score, bnb->score, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Guesses, CorrelativeSearchTest,
                         ::testing::Values(Rigid2d(0.3, 0.0, 0.0), Rigid2d(-0.3, 0.3, 0.0),
                                           Rigid2d(0.0, 0.0, 0.17), Rigid2d(0.3, -0.3, -0.17),
                                           Rigid2d(-0.2, -0.25, 0.1)));

TEST(CorrelativeSearchBadInputTest, EmptyInputsGiveNoMatch) {
  const MatchGrid empty;
  const std::vector<Eigen::Vector2f> points = {Eigen::Vector2f(1.0f, 0.0f)};
  CorrelativeSearchOptions options;
  EXPECT_FALSE(SearchBruteForce(points, empty, Rigid2d(), options));
  EXPECT_FALSE(SearchBranchAndBound({}, MatchGridPyramid(empty), Rigid2d(), options));
  const MatchGrid grid = testing::WorldGrid(testing::FurnishedRoom());
  EXPECT_FALSE(SearchBruteForce(points, grid, Rigid2d(NAN, 0.0, 0.0), options));
  options.linear_window = -1.0;
  EXPECT_FALSE(SearchBruteForce(points, grid, Rigid2d(), options));
}

TEST(CorrelativeSearchBadInputTest, MinScoreRejectsAPoorFit) {
  const MatchGrid grid = testing::WorldGrid(testing::FurnishedRoom());
  // Points in a pattern that exists nowhere in the room.
  std::vector<Eigen::Vector2f> points;
  for (int i = 0; i < 50; ++i) points.emplace_back(0.5f + 0.02f * i, 0.3f * (i % 3));
  CorrelativeSearchOptions options;
  options.min_score = 0.9;
  EXPECT_FALSE(SearchBranchAndBound(points, MatchGridPyramid(grid), Rigid2d(), options));
}

}  // namespace
}  // namespace fleetmap

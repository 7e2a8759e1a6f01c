// Parts no submap match places are matched whole (MergeEngineOptions::whole_map_matches): the
// best alignment of one whole map on the other becomes a hypothesis, accepted only when another
// submap confirms it and nothing fits as well over the whole maps.

#include <gtest/gtest.h>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_engine_fixtures.h"

namespace fleetmap {
namespace {

using merge_fixtures::EstimatedRelative;
using merge_fixtures::Feed;
using merge_fixtures::SimRobot;
using merge_fixtures::TrueRelative;

// No submap is searched on its own (as when every one is ambiguous, like the building's plain
// corridors): only the whole maps can place the robots.
MergeEngineOptions WholeMapsOnly(bool whole_map_matches) {
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 0;
  options.whole_map_matches = whole_map_matches;
  return options;
}

void UpdateUntilSettled(MergeEngine* engine) {
  for (int i = 0; i == 0 || (i < 20 && engine->HasPendingWork()); ++i) engine->Update();
}

// Robots a and b tour the office's left and middle rooms in opposite directions, their starts
// unknown to each other; b's local frame is turned by any heading.
class WholeMapMatchTest : public ::testing::TestWithParam<double> {};

TEST_P(WholeMapMatchTest, TheWholeMapsPlaceRobotsNoSubmapMatchPlaced) {
  const SimRobot a = merge_fixtures::RobotA(), b = merge_fixtures::RobotB(GetParam());
  MergeEngine engine(WholeMapsOnly(true));
  Feed(testing::OfficeWorld(), a, &engine);
  Feed(testing::OfficeWorld(), b, &engine);
  UpdateUntilSettled(&engine);
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel) << "b was not placed";
  const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
  EXPECT_LT(error.translation().norm(), 0.05);
  EXPECT_LT(std::abs(error.rotation()), 0.01);
}

INSTANTIATE_TEST_SUITE_P(Headings, WholeMapMatchTest, ::testing::Values(-3.0, -1.2, 0.4, 2.4));

// a tours the office's left and middle rooms twice. b starts in the office's right rooms, which
// a never saw, and only then drives through the middle room into the left one. The whole-map
// alignment of b's (smaller) map on a's is confirmed by another submap of b only where that
// lands on a's map: b's first submaps (by id) cannot confirm it.
TEST(WholeMapMatchVerifyTest, SubmapsLandingOnTheOtherMapConfirmTheWholeMaps) {
  const std::vector<Rigid2d> a_path = testing::PathThrough(
      {{2, 6}, {6, 6}, {10, 6}, {10, 10}, {11, 10.5}, {10, 6}, {6, 6}, {3.5, 5}, {3.5, 9}}, 0.25);
  const SimRobot a{"a", a_path, Rigid2d(2, 6, 0.3)};
  const std::vector<Rigid2d> b_path = testing::PathThrough(
      {{15, 10}, {18.5, 10}, {18.5, 2.5}, {14.5, 3}, {14, 5}, {10, 6}, {6, 6.3}}, 0.25);
  const SimRobot b{"b", b_path, Rigid2d(b_path.front().translation(), 2.4)};
  MergeEngine engine(WholeMapsOnly(true));
  Feed(testing::OfficeWorld(), a, &engine);
  Feed(testing::OfficeWorld(), b, &engine);
  std::string reasons;
  for (int i = 0; i == 0 || (i < 20 && engine.HasPendingWork()); ++i) {
    for (const AlignmentEvent& e : engine.Update().events) reasons += e.reason + "\n";
  }
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel) << "b was not placed:\n" << reasons;
  const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
  EXPECT_LT(error.translation().norm(), 0.05) << reasons;
  EXPECT_LT(std::abs(error.rotation()), 0.01) << reasons;
  EXPECT_NE(reasons.find("whole maps matched"), std::string::npos) << reasons;
}

TEST(WholeMapMatchOffTest, WithoutWholeMapMatchesTheRobotsStayApart) {
  const SimRobot a = merge_fixtures::RobotA(), b = merge_fixtures::RobotB(0.4);
  MergeEngine engine(WholeMapsOnly(false));
  Feed(testing::OfficeWorld(), a, &engine);
  Feed(testing::OfficeWorld(), b, &engine);
  UpdateUntilSettled(&engine);
  EXPECT_FALSE(EstimatedRelative(engine, "a", "b"));
}

// The twin offices (the office and beside it the office turned half round, like the simulator's
// department): a drives the turned office's rooms and then the office's right and middle rooms,
// b the office. Over b's whole map the true and the turned alignments fit alike, so whichever
// the whole-map match finds, the join must wait.
TEST(WholeMapMatchTwinTest, AWholeMapMatchWaitsWhileTheMapsFitTurnedRound) {
  const testing::SegmentWorld world = testing::TwinOffices();
  std::vector<Rigid2d> a_path;
  const auto tour = testing::PathThrough({{2, 6}, {5.5, 5.5}, {8, 6}, {11, 5}, {14, 5}, {18.5, 5},
                                          {18.5, 9}, {14, 9}, {18.5, 9}, {18.5, 5}, {11, 6}},
                                         0.25);
  for (const Rigid2d& p : tour) a_path.push_back(testing::TwinOfficesHalfTurn() * p);
  for (const Rigid2d& p : testing::PathThrough({{21.5, 6}, {18.5, 6}, {18.5, 9}, {14.5, 9},
                                                {18.5, 9}, {18.5, 5}, {14, 5}, {11, 6}},
                                               0.25)) {
    a_path.push_back(p);
  }
  const SimRobot a{"a", a_path, Rigid2d(a_path.front().translation(), 0.4)};
  const std::vector<Rigid2d> b_path =
      testing::PathThrough({{8, 6}, {11.5, 5}, {14, 5}, {18.5, 5}, {18.5, 9}, {14.5, 9}, {18.5, 9}}, 0.25);
  const SimRobot b{"b", b_path, Rigid2d(b_path.front().translation(), -1.1)};
  MergeEngine engine(WholeMapsOnly(true));
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  bool matched = false;
  for (int i = 0; i == 0 || (i < 20 && engine.HasPendingWork()); ++i) {
    for (const AlignmentEvent& e : engine.Update().events) {
      matched |= e.reason.find("whole maps matched") != std::string::npos;
    }
  }
  EXPECT_TRUE(matched) << "the whole maps were never matched: the case is not the one meant";
  const auto rel = EstimatedRelative(engine, "a", "b");
  if (rel) {
    const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
    ADD_FAILURE() << "joined " << error.translation().norm() << " m, "
                  << std::abs(error.rotation()) * 180.0 / M_PI << " deg off";
  }
}

}  // namespace
}  // namespace fleetmap

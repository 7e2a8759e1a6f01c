// An alternative alignment that explains more of the whole maps than the join (scores more)
// is ruled out by the walls it puts where the other map saw through, counted with each tile
// fitted as the join's are (MergeEngineOptions::whole_map_rule_out_higher); without that
// option, or without such walls, it keeps the join waiting.

#include <gtest/gtest.h>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_engine_fixtures.h"

namespace fleetmap {
namespace {

using merge_fixtures::EstimatedRelative;
using merge_fixtures::Feed;
using merge_fixtures::SimRobot;
using merge_fixtures::TrueRelative;

// The twin offices (the office, and beside it the office turned half round). Robot a tours the
// office's three rooms. Robot b starts in the office's middle room, drives through its right
// room and the door into the turned twin, and tours the twin's three rooms. b's submaps in the
// office match a's map where they are; over b's whole map the half-turned alignment (the twin's
// rooms on the office's) lands more of it on a's map and scores more. With `crates` the office
// holds two crates the twin lacks: turned, b's map puts the twin's empty rooms over a's crates.
std::unique_ptr<MergeEngine> RoomsTurnedEngine(bool rule_out_higher, bool crates, SimRobot* a,
                                               SimRobot* b) {
  const std::vector<Rigid2d> a_path = testing::PathThrough(
      {{2, 6}, {5.5, 5.5}, {8, 6}, {11, 5}, {14, 5}, {18.5, 5}, {18.5, 9}, {14, 9}, {18.5, 9}},
      0.25);
  *a = SimRobot{"a", a_path, Rigid2d(a_path.front().translation(), 0.4)};
  const std::vector<Rigid2d> b_path =
      testing::PathThrough({{8, 6},
                            {11, 5},
                            {14, 5},
                            {14, 9},
                            {18.5, 9},
                            {18.5, 6},
                            {21.5, 6},
                            {21.5, 3},
                            {26, 3},
                            {21.5, 3},
                            {21.5, 7},
                            {26, 7},
                            {29, 7},
                            {32, 6},
                            {34.5, 6.5},
                            {38, 6}},
                           0.25);
  *b = SimRobot{"b", b_path, Rigid2d(b_path.front().translation(), -1.1)};
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 100;
  options.whole_map_rule_out_higher = rule_out_higher;
  auto engine = std::make_unique<MergeEngine>(options);
  const testing::SegmentWorld world = testing::TwinOffices(crates);
  Feed(world, *a, engine.get());
  Feed(world, *b, engine.get());
  return engine;
}

// Five updates (every submap searched in the first); the reasons their events gave.
std::string RunUpdates(MergeEngine* engine) {
  std::string reasons;
  for (int i = 0; i < 5; ++i) {
    for (const AlignmentEvent& e : engine->Update().events) reasons += e.reason + "\n";
  }
  return reasons;
}

TEST(MergeEngineRuleOutHigherTest, TheCratesRuleOutTheTurnedRoomsScoringMore) {
  SimRobot a, b;
  auto engine = RoomsTurnedEngine(/*rule_out_higher=*/true, /*crates=*/true, &a, &b);
  const std::string reasons = RunUpdates(engine.get());
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel) << reasons;
  const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
  EXPECT_LT(error.translation().norm(), 0.05) << reasons;
  EXPECT_LT(std::abs(error.rotation()), 0.01) << reasons;
  // The turned rooms (49 points against the join's 2 when written).
  EXPECT_NE(reasons.find("walls rule out"), std::string::npos) << reasons;
  EXPECT_NE(reasons.find("180 deg away: "), std::string::npos) << reasons;
}

// b waits, kept off by the turned rooms scoring more.
void ExpectTheJoinToWaitOnTheTurnedRooms(bool rule_out_higher, bool crates) {
  SimRobot a, b;
  auto engine = RoomsTurnedEngine(rule_out_higher, crates, &a, &b);
  const std::string reasons = RunUpdates(engine.get());
  EXPECT_FALSE(engine->RobotToGlobal("b")) << reasons;
  EXPECT_NE(reasons.find("ambiguous over the whole maps"), std::string::npos) << reasons;
  // Found by the search, or as the join's twin under a map's own symmetry (the turned rooms).
  EXPECT_NE(reasons.find("180 deg away"), std::string::npos) << reasons;
  EXPECT_NE(reasons.find("fits as well"), std::string::npos) << reasons;
}

TEST(MergeEngineRuleOutHigherTest, WithoutTheOptionTheTurnedRoomsKeepTheJoinWaiting) {
  ExpectTheJoinToWaitOnTheTurnedRooms(/*rule_out_higher=*/false, /*crates=*/true);
}

// Twins alike: nothing in the maps tells the turned rooms from the true ones, so the join waits
// whatever the option.
TEST(MergeEngineRuleOutHigherTest, WithoutCratesTheTurnedRoomsKeepTheJoinWaiting) {
  ExpectTheJoinToWaitOnTheTurnedRooms(/*rule_out_higher=*/true, /*crates=*/false);
}

}  // namespace
}  // namespace fleetmap

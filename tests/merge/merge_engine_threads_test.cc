// An Update() runs its global searches ahead, and its local constraint and loop closure searches
// and then their edges' refinement, side by side (MergeEngineOptions::search_threads). What goes
// into the graph, in what order, and what the events say must not depend on how many threads
// ran them, nor on whether the global searches ran ahead.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_engine_fixtures.h"
#include "tests/merge/merge_test_worlds.h"

namespace fleetmap {
namespace {

using namespace merge_fixtures;

struct FleetRun {
  std::unique_ptr<MergeEngine> engine;
  std::vector<std::string> events;  // every update's events, in order
};

void Record(const MergeUpdate& update, FleetRun* run) {
  for (const AlignmentEvent& e : update.events) {
    run->events.push_back(std::string(AlignmentEventTypeName(e.type)) + " " + e.robot_a + " <- " +
                          e.robot_b + " score " + std::to_string(e.score) + ": " + e.reason);
  }
}

// Robots a and b joined by two detections, then tied by local constraints on both sides; robot c
// drives a loop with drifting anchors, closed against its own first submaps.
FleetRun Fleet(int threads) {
  MergeEngineOptions options = TestOptions();
  options.search_threads = threads;
  options.max_loop_searches_per_update = 100;
  FleetRun run{std::make_unique<MergeEngine>(options), {}};
  const testing::SegmentWorld world = testing::OfficeWorld();
  const SimRobot a = RobotA(), b = RobotB(-1.0);
  Feed(world, a, run.engine.get());
  Feed(world, b, run.engine.get());
  EXPECT_TRUE(run.engine->AddDetection(Detect(a, b, 20, false)));
  EXPECT_TRUE(run.engine->AddDetection(Detect(a, b, 24, false)));
  const std::vector<Rigid2d> loop =
      testing::PathThrough({{8, 1.2}, {12, 1.2}, {12, 7}, {8, 7.2}, {8, 1.2}, {11, 1.2}}, 0.25);
  for (Submap s : testing::MakeSubmaps("c", world, loop, Rigid2d(), 5)) {
    const double k = static_cast<double>(s.submap_id);
    s.submap_in_local = Rigid2d(0.005 * k, 0.0, 0.001 * k) * s.submap_in_local;
    EXPECT_TRUE(run.engine->AddOrUpdateSubmap(s));
  }
  for (int i = 0; i < 20 && (i == 0 || run.engine->HasPendingWork()); ++i) {
    Record(run.engine->Update(), &run);
  }
  return run;
}

// Three robots and no detections: every new submap is searched over the other parts' whole
// maps (up to 4 per update), and joins happen between those searches.
FleetRun Searching(int threads) {
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.search_threads = threads;
  FleetRun run{std::make_unique<MergeEngine>(options), {}};
  const testing::SegmentWorld world = testing::OfficeWorld();
  SimRobot c = RobotB(2.0);
  c.id = "c";
  for (const SimRobot& robot : {RobotA(), RobotB(-1.0), c}) Feed(world, robot, run.engine.get());
  for (int i = 0; i < 40 && (i == 0 || run.engine->HasPendingWork()); ++i) {
    Record(run.engine->Update(), &run);
  }
  return run;
}

void ExpectSameRun(const FleetRun& one, const FleetRun& many) {
  EXPECT_EQ(many.events, one.events);
  const std::vector<RelativeEdge>& expected = one.engine->graph().edges();
  const std::vector<RelativeEdge>& edges = many.engine->graph().edges();
  ASSERT_EQ(edges.size(), expected.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    SCOPED_TRACE("edge " + std::to_string(i));
    EXPECT_TRUE(edges[i].from == expected[i].from);
    EXPECT_TRUE(edges[i].to == expected[i].to);
    EXPECT_EQ(edges[i].kind, expected[i].kind);
    EXPECT_EQ(edges[i].to_in_from.translation(), expected[i].to_in_from.translation());
    EXPECT_EQ(edges[i].to_in_from.rotation(), expected[i].to_in_from.rotation());
  }
  const auto expected_poses = one.engine->SubmapPoses();
  const auto poses = many.engine->SubmapPoses();
  ASSERT_EQ(poses.size(), expected_poses.size());
  for (const auto& [id, pose] : expected_poses) {
    EXPECT_EQ(poses.at(id).translation(), pose.translation()) << id.robot << "/" << id.submap;
    EXPECT_EQ(poses.at(id).rotation(), pose.rotation()) << id.robot << "/" << id.submap;
  }
}

TEST(MergeEngineThreadsTest, TheGraphDoesNotDependOnTheThreadCount) {
  const FleetRun one = Fleet(1);
  // The case must exercise both kinds of search, several per update.
  int local = 0, loops = 0;
  for (const RelativeEdge& e : one.engine->graph().edges()) {
    local += e.kind == EdgeKind::kCrossMatch && e.from.robot != e.to.robot;
    loops += e.kind == EdgeKind::kLoopClosure;
  }
  EXPECT_GE(local, 6);
  EXPECT_GE(loops, 2);
  EXPECT_EQ(one.engine->PlacedRobots().size(), 2u);

  for (int threads : {2, 3}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    ExpectSameRun(one, Fleet(threads));
  }
}

TEST(MergeEngineThreadsTest, GlobalSearchesAndJoinsDoNotDependOnTheThreadCount) {
  const FleetRun one = Searching(1);
  // Both joins come from global searches, after searches the gates rejected.
  int accepted = 0, rejected = 0;
  for (const std::string& e : one.events) {
    accepted += e.rfind("alignment accepted", 0) == 0;
    rejected += e.rfind("rejected", 0) == 0;
  }
  EXPECT_EQ(accepted, 2);
  EXPECT_GE(rejected, 1);
  EXPECT_EQ(one.engine->PlacedRobots().size(), 3u);
  for (int threads : {2, 3}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    ExpectSameRun(one, Searching(threads));
  }
}

// c stays in the right room, d drives from the middle room into it, and e tours the left and
// middle rooms: c overlaps d only, and e overlaps d only. The robots are searched in name order.
// The events of each update end with a marker, so that they must also fall in the same update.
FleetRun ThreeRooms(int threads, bool ahead) {
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.search_threads = threads;
  options.max_global_searches_per_update = 100;
  options.search_ahead = ahead;
  FleetRun run{std::make_unique<MergeEngine>(options), {}};
  const testing::SegmentWorld world = testing::OfficeWorld();
  const SimRobot c{
      "c", testing::PathThrough({{14.5, 5}, {18.5, 5}, {18.5, 6.5}, {15, 6.5}, {14.5, 3}}, 0.25),
      Rigid2d(14.5, 5, -2.0)};
  const SimRobot d{"d",
                   testing::PathThrough({{8, 6}, {11, 5}, {15, 5}, {18.5, 5}, {18.5, 3}}, 0.25),
                   Rigid2d(8, 6, 1.0)};
  SimRobot e = RobotA();
  e.id = "e";
  for (const SimRobot& robot : {c, d, e}) Feed(world, robot, run.engine.get());
  for (int i = 0; i < 40 && (i == 0 || run.engine->HasPendingWork()); ++i) {
    Record(run.engine->Update(), &run);
    run.events.push_back("UPDATE " + std::to_string(i));
  }
  return run;
}

// Every search in one update: c and d join, and then robot e's submaps are searched over the
// joined part, whose map the join changed after the searches ran ahead. Those must run again, so
// that the run is the one where each search runs when its turn comes.
TEST(MergeEngineThreadsTest, SearchesOverAPartAJoinChangedRunAgain) {
  const FleetRun in_turn = ThreeRooms(1, false);
  // e stays apart: the middle room fits d's map as well turned half round.
  EXPECT_EQ(in_turn.engine->PlacedRobots(), (std::vector<std::string>{"c", "d"}));
  const FleetRun ahead = ThreeRooms(2, true);
  EXPECT_GT(ahead.engine->global_searches_in_turn(), 0);
  EXPECT_LT(ahead.engine->global_searches_in_turn(), in_turn.engine->global_searches_in_turn());
  ExpectSameRun(in_turn, ahead);
}

}  // namespace
}  // namespace fleetmap

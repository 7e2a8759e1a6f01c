// An Update() runs its global searches ahead, and its local constraint and loop closure searches
// and then their edges' refinement, side by side (MergeEngineOptions::search_threads). What goes
// into the graph, in what order, and what the events say must not depend on how many threads
// ran them.

#include <gtest/gtest.h>

#include <cstdio>
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
  MergeEngineOptions options;
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
  for (const std::string& e : one.events) std::printf("EV %s\n", e.c_str());
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

}  // namespace
}  // namespace fleetmap

#ifndef FLEETMAP_TESTS_MERGE_MERGE_ENGINE_FIXTURES_H_
#define FLEETMAP_TESTS_MERGE_MERGE_ENGINE_FIXTURES_H_

// Simulated robots, detections and engines with known answers, shared by the merge engine's
// test files.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_test_worlds.h"

namespace fleetmap::merge_fixtures {

constexpr double kDt = 0.5;

struct SimRobot {
  std::string id;
  std::vector<Rigid2d> path;  // world poses, one per kDt
  Rigid2d local_in_world;
};

// Robot "a" tours the office's left and middle rooms; "b" tours them the other way round.
SimRobot RobotA();
SimRobot RobotB(double heading);

// The robot's submaps (10 scans each) and trajectory into the engine (gtest assertions).
void Feed(const testing::SegmentWorld& world, const SimRobot& robot, MergeEngine* engine);
// An exact detection of `observed` by `observer` at path index `step`.
RobotDetection Detect(const SimRobot& observer, const SimRobot& observed, size_t step, bool heading);

// b's local frame in a's local frame: the truth, and the engine's estimate (when both placed).
Rigid2d TrueRelative(const SimRobot& a, const SimRobot& b);
std::optional<Rigid2d> EstimatedRelative(const MergeEngine& engine, const std::string& a, const std::string& b);

int Count(const MergeUpdate& u, AlignmentEventType type);
// Default options, but a join on matches alone is made as soon as it passes every gate. The
// tests here judge those gates, mostly on maps fed at once, where no growth would end a
// probation (MergeEngineOptions::match_join_probation_growth, tested on its own in
// merge_engine_verify_test.cc and merge_engine_join_review_test.cc); and a test that a join is
// not made must not pass because the join is only held.
MergeEngineOptions GateOptions();
// Detections only (no global searches) unless a test wants more.
MergeEngineOptions TestOptions();

// In the corridor world, a drives 10 m and waits; b comes 12 m towards it from the far end.
std::pair<SimRobot, SimRobot> FeedCorridorApproach(MergeEngine* engine);
// An engine that searches without detections, fed robots a and b (whose maps overlap).
std::unique_ptr<MergeEngine> OverlappingRobotsWithSearches(const SimRobot& a, const SimRobot& b);

}  // namespace fleetmap::merge_fixtures

#endif  // FLEETMAP_TESTS_MERGE_MERGE_ENGINE_FIXTURES_H_

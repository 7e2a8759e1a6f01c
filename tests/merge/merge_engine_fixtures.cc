#include "tests/merge/merge_engine_fixtures.h"

#include <gtest/gtest.h>

namespace fleetmap::merge_fixtures {

SimRobot RobotA() {
  return {"a", testing::PathThrough({{2, 6}, {6, 6}, {10, 6}, {10, 10}, {11, 10.5}}, 0.25), Rigid2d(2, 6, 0.3)};
}
SimRobot RobotB(double heading) {
  return {"b", testing::PathThrough({{11, 10}, {10, 6}, {6, 6.3}, {3.5, 5}, {3.5, 8}}, 0.25),
          Rigid2d(11, 10, heading)};
}

void Feed(const testing::SegmentWorld& world, const SimRobot& robot, MergeEngine* engine) {
  for (const Submap& s : testing::MakeSubmaps(robot.id, world, robot.path, robot.local_in_world, 10, kDt)) {
    std::string error;
    ASSERT_TRUE(engine->AddOrUpdateSubmap(s, &error)) << error;
  }
  ASSERT_TRUE(engine->SetTrajectory(robot.id, testing::MakeTrajectory(robot.path, robot.local_in_world, kDt)));
}

RobotDetection Detect(const SimRobot& observer, const SimRobot& observed, size_t step, bool heading) {
  RobotDetection d;
  d.observer_id = observer.id;
  d.observed_id = observed.id;
  d.timestamp = static_cast<double>(step) * kDt;
  const Rigid2d rel = observer.path[step].inverse() * observed.path[step];
  d.position_in_observer = rel.translation();
  d.covariance = Eigen::Matrix2d::Identity() * 0.02 * 0.02;
  if (heading) {
    d.relative_heading = rel.rotation();
    d.relative_heading_variance = 0.02 * 0.02;
  }
  return d;
}

Rigid2d TrueRelative(const SimRobot& a, const SimRobot& b) { return a.local_in_world.inverse() * b.local_in_world; }

std::optional<Rigid2d> EstimatedRelative(const MergeEngine& engine, const std::string& a, const std::string& b) {
  const auto ga = engine.RobotToGlobal(a), gb = engine.RobotToGlobal(b);
  if (!ga || !gb) return std::nullopt;
  return ga->inverse() * *gb;
}

int Count(const MergeUpdate& u, AlignmentEventType type) {
  int n = 0;
  for (const AlignmentEvent& e : u.events) n += e.type == type;
  return n;
}

MergeEngineOptions GateOptions() {
  MergeEngineOptions options;
  options.match_join_probation_growth = 0.0;
  return options;
}

MergeEngineOptions TestOptions() {
  MergeEngineOptions options = GateOptions();
  options.max_global_searches_per_update = 0;
  options.whole_map_matches = false;  // a global search too
  return options;
}

std::pair<SimRobot, SimRobot> FeedCorridorApproach(MergeEngine* engine) {
  const testing::SegmentWorld world = testing::CorridorWorld();
  SimRobot a{"a", testing::PathThrough({{2, 1}, {12, 1}}, 0.25), Rigid2d(2, 1, 0.0)};
  const SimRobot b{"b", testing::PathThrough({{28, 1}, {16, 1}}, 0.25), Rigid2d(28, 1, 0.7)};
  while (a.path.size() < b.path.size()) a.path.push_back(a.path.back());
  Feed(world, a, engine);
  Feed(world, b, engine);
  return {a, b};
}

std::unique_ptr<MergeEngine> OverlappingRobotsWithSearches(const SimRobot& a, const SimRobot& b) {
  MergeEngineOptions options = GateOptions();
  options.max_global_searches_per_update = 100;
  auto engine = std::make_unique<MergeEngine>(options);
  const testing::SegmentWorld world = testing::OfficeWorld();
  Feed(world, a, engine.get());
  Feed(world, b, engine.get());
  return engine;
}

}  // namespace fleetmap::merge_fixtures

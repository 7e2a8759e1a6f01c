#include "robot_agent/localization/tool/sim_replay.h"

#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot_agent/sim/world_io.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(FirstLocalizedTimeTest, NeedsTheWholeHoldWithinTolerance) {
  ErrorSeries position, heading;
  const double errors[] = {5.0, 0.1, 0.3, 0.1, 0.1, 0.1, 0.1};
  for (int i = 0; i < 7; ++i) {
    position.points.emplace_back(i, errors[i]);
    heading.points.emplace_back(i, 0.01);
  }
  EXPECT_DOUBLE_EQ(FirstLocalizedTime(position, heading, 0.2, 0.1, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(FirstLocalizedTime(position, heading, 0.5, 0.1, 3.0), 1.0);
  EXPECT_DOUBLE_EQ(FirstLocalizedTime(position, heading, 0.2, 0.1, 4.0), -1.0);  // cut by the end
  heading.points[4].second = 1.0;
  EXPECT_DOUBLE_EQ(FirstLocalizedTime(position, heading, 0.2, 0.1, 2.0), -1.0);
}

// The Fig. 21-22 case, one short seeded run: robot2 (known start) sees robot1 (uniform belief)
// at about 8 s; robot1 must be localized within 2 s of that detection.
TEST(SimLocalizationTest, DetectionLocalizesTheLostRobot) {
  sim::Scenario scenario;
  std::string error;
  ASSERT_TRUE(sim::LoadScenario(
      testing::SourceDir() + "/robot_agent/localization/scenarios/department_fig22.yaml",
      &scenario, &error))
      << error;
  sim::World world;
  ASSERT_TRUE(sim::LoadWorld(scenario.world_path, &world, &error)) << error;
  OccupancyGrid map;
  ASSERT_TRUE(LoadWorldMap(scenario.world_path, &map, &error)) << error;

  SimLocalizationOptions options;
  options.particles = 3000;
  options.max_time = 14.0;
  options.hold_time = 3.0;
  SimRunResult result;
  ASSERT_TRUE(RunSimLocalization(scenario, world, map, options, &result, &error)) << error;
  ASSERT_EQ(result.robots.size(), 2u);
  ASSERT_GE(result.first_detection_time, 0.0);
  EXPECT_GE(result.first_detection_time, result.first_visible_time);
  const SimRobotResult& lost = result.robots[0];
  ASSERT_GE(lost.time_localized, 0.0);
  EXPECT_LE(lost.time_localized, result.first_detection_time + 2.0);
  EXPECT_TRUE(lost.localized_at_end);
  // Before the detection the lost robot was not localized (the detection did the work).
  EXPECT_GT(lost.position_error.points.front().second, options.position_tolerance);
  // The observer stayed localized throughout.
  EXPECT_GE(result.robots[1].time_localized, 0.0);
  EXPECT_LE(result.robots[1].time_localized, 1.0);
}

// A run of `fleetmap-localize sim --seed 201` (run 36) where robot1 sat on a look-alike place
// 45 m off when the first detection came: the detection was taken as confirming that belief,
// and robot1 waited 4.4 s for the next one (with 2 s between detections of a pair).
TEST(SimLocalizationTest, ALostRobotOnALookAlikePlaceIsLocalizedByTheFirstDetections) {
  sim::Scenario scenario;
  std::string error;
  ASSERT_TRUE(sim::LoadScenario(
      testing::SourceDir() + "/robot_agent/localization/scenarios/department_fig22.yaml", &scenario,
      &error))
      << error;
  scenario.seed += 36;
  sim::World world;
  ASSERT_TRUE(sim::LoadWorld(scenario.world_path, &world, &error)) << error;
  OccupancyGrid map;
  ASSERT_TRUE(LoadWorldMap(scenario.world_path, &map, &error)) << error;

  SimLocalizationOptions options;
  options.seed = 201 + 36;
  options.max_time = 16.0;
  options.hold_time = 3.0;
  SimRunResult result;
  ASSERT_TRUE(RunSimLocalization(scenario, world, map, options, &result, &error)) << error;
  ASSERT_GE(result.first_detection_time, 0.0);
  const SimRobotResult& lost = result.robots[0];
  ASSERT_GE(lost.time_localized, 0.0);
  EXPECT_LE(lost.time_localized, result.first_detection_time + 2.0);
  EXPECT_TRUE(lost.localized_at_end);
}

TEST(SimLocalizationTest, RejectsABadLostRobotIndex) {
  sim::Scenario scenario;
  std::string error;
  ASSERT_TRUE(sim::LoadScenario(
      testing::SourceDir() + "/robot_agent/localization/scenarios/department_fig22.yaml",
      &scenario, &error))
      << error;
  sim::World world;
  ASSERT_TRUE(sim::LoadWorld(scenario.world_path, &world, &error)) << error;
  OccupancyGrid map;
  ASSERT_TRUE(LoadWorldMap(scenario.world_path, &map, &error)) << error;
  SimLocalizationOptions options;
  options.lost_robot = 5;
  SimRunResult result;
  EXPECT_FALSE(RunSimLocalization(scenario, world, map, options, &result, &error));
  EXPECT_THAT(error, ::testing::HasSubstr("out of range"));
}

}  // namespace
}  // namespace fleetmap

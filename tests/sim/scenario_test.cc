#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/simulation.h"
#include "robot_agent/sim/world_builder.h"
#include "robot_agent/sim/world_io.h"
#include "tests/support/test_support.h"

namespace fleetmap::sim {
namespace {

using ::testing::HasSubstr;

// Parses `text` (worlds looked up in the shipped folder) and builds the simulation; returns the
// error, empty on success.
std::string Check(const std::string& text, const std::string& base_dir = ".") {
  Scenario scenario;
  std::string error;
  if (!ParseScenario(text, base_dir, &scenario, &error)) return error;
  World world;
  if (!LoadWorld(scenario.world_path, &world, &error)) return error;
  if (!Simulation::Create(scenario, std::move(world), &error)) return error;
  return "";
}

const char kValid[] = R"(
world: rectangle
robots:
  - name: r1
    start: Corner_SW
    route: {waypoints: [Corner_SE], speed: 0.5}
)";

TEST(ScenarioTest, ValidScenarioPasses) { EXPECT_EQ(Check(kValid), ""); }

TEST(ScenarioTest, UnknownWorldIsNamed) {
  EXPECT_THAT(Check("world: atlantis\nrobots: [{start: {x: 1, y: 1}}]\n"),
              HasSubstr("unknown world 'atlantis'"));
}

TEST(ScenarioTest, RobotStartingInsideAWallFails) {
  // (10, 8) lies in the rectangle's solid inner block.
  EXPECT_THAT(Check("world: rectangle\nrobots: [{name: r1, start: {x: 10, y: 8}}]\n"),
              HasSubstr("r1: start (10, 8) is inside a wall"));
}

TEST(ScenarioTest, NegativeSpeedFails) {
  EXPECT_THAT(Check("world: rectangle\nrobots:\n  - start: Corner_SW\n"
                    "    route: {waypoints: [Corner_SE], speed: -0.5}\n"),
              HasSubstr("robots[0].route.speed: must be > 0, got -0.5"));
}

TEST(ScenarioTest, UnknownPlaceAndTypoAreNamed) {
  EXPECT_THAT(Check("world: rectangle\nrobots:\n  - start: Corner_SW\n"
                    "    route: {waypoints: [Lab_9]}\n"),
              HasSubstr("waypoint 1 'Lab_9' is not a place"));
  EXPECT_THAT(Check("world: rectangle\nrobots:\n  - start: Corner_SW\n"
                    "    route: {waypoints: [Corner_SE], sped: 1}\n"),
              HasSubstr("robots[0].route.sped: unknown key"));
}

TEST(ScenarioTest, UnreachableWaypointFails) {
  // Two rooms with no door between them.
  const testing::ScopedTempDir temp("sim_unreachable");
  const std::string& dir = temp.path();
  WorldBuilder builder("two_rooms", 0.05, Eigen::Vector2d(10.0, 5.0));
  builder.Carve({0.2, 0.2}, {4.8, 4.8});
  builder.Carve({5.2, 0.2}, {9.8, 4.8});
  std::string error;
  ASSERT_TRUE(SaveWorld(dir, builder.Build(), &error)) << error;
  EXPECT_THAT(Check("world: two_rooms.world.yaml\nrobots:\n  - name: r1\n"
                    "    start: {x: 2, y: 2}\n    route: {waypoints: [[3, 3], [7, 2]]}\n",
                    dir),
              HasSubstr("r1: waypoint 2 (7, 2) at (7, 2) is unreachable"));
}

TEST(ScenarioTest, MalformedYamlAndBadNumbersFailCleanly) {
  EXPECT_THAT(Check("world: [unclosed\n"), HasSubstr("invalid YAML"));
  EXPECT_THAT(Check("world: rectangle\nseed: -3\nrobots: [{start: Corner_SW}]\n"),
              HasSubstr("seed"));
  EXPECT_THAT(Check("world: rectangle\nlaser: {beams: abc}\nrobots: [{start: Corner_SW}]\n"),
              HasSubstr("laser.beams: expected an integer"));
  EXPECT_THAT(Check("world: rectangle\nrobots: []\n"), HasSubstr("non-empty list"));
}

TEST(ScenarioTest, EveryShippedScenarioLoadsValidatesAndRuns) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(ShippedScenariosDir())) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    std::string error;
    std::unique_ptr<Simulation> sim =
        Simulation::FromFile(entry.path().string(), &error, /*camera_enabled=*/false);
    ASSERT_NE(sim, nullptr) << error;
    sim->set_end_time(sim->time() + 2.0);
    int scans = 0;
    while (!sim->Done()) {
      for (const SensorPacket& packet : sim->Step().packets) scans += packet.laser.has_value();
    }
    EXPECT_EQ(scans, 20 * static_cast<int>(sim->robots().size()));
    ++count;
  }
  EXPECT_GE(count, 10);
}

TEST(ScenarioTest, BuildingLapIsOver400Metres) {
  std::string error;
  std::unique_ptr<Simulation> sim =
      Simulation::FromFile(ShippedScenariosDir() + "/building_1lap.yaml", &error, false);
  ASSERT_NE(sim, nullptr) << error;
  EXPECT_GT(PathLength(sim->robots()[0].route.path), 400.0);
}

}  // namespace
}  // namespace fleetmap::sim

#include "robot_agent/agent/agent_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using ::testing::HasSubstr;

class AgentConfigTest : public ::testing::Test {
 protected:
  void SetUp() override { std::ofstream(dir_.path() + "/robot.log") << "# empty log\n"; }
  std::string Base() const {
    return R"(
robot:
  id: r1
  name: Robot one
  start_pose: {x: 1.5, y: -2, theta: 0.5}
server:
  address: 127.0.0.1:50051
outbox:
  path: r1-outbox.db
slam:
  algorithm: scan-matching
  resolution: 0.05
  submap_scans: 50
source:
  carmen:
    log: robot.log
  speed: realtime
upload:
  batch_size: 16
  backoff: {initial: 0.1, multiplier: 2, max: 5, jitter: 0.1}
  trajectory_period: 2
map:
  file: global
status:
  period: 1
)";
  }
  // Base() with `from` replaced by `to` (which must occur).
  std::string With(const std::string& from, const std::string& to) const {
    std::string text = Base();
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  }
  bool Parse(const std::string& text, AgentConfig* config, std::string* error) const {
    return ParseAgentConfig(text, "robot.yaml", dir_.path(), config, error);
  }
  const testing::ScopedTempDir dir_{"agent_config"};
};

TEST_F(AgentConfigTest, ParsesEveryField) {
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(Parse(Base(), &config, &error)) << error;
  EXPECT_EQ(config.robot_id, "r1");
  EXPECT_EQ(config.robot_name, "Robot one");
  ASSERT_TRUE(config.start_pose.has_value());
  EXPECT_THAT(*config.start_pose, testing::IsNearPose(Rigid2d(1.5, -2.0, 0.5), 1e-12, 1e-12));
  EXPECT_EQ(config.server_address, "127.0.0.1:50051");
  EXPECT_EQ(config.outbox_path, dir_.path() + "/r1-outbox.db");  // relative to the file
  EXPECT_EQ(config.slam.submap_scans, 50);
  EXPECT_EQ(config.source.type, SourceConfig::Type::kCarmen);
  EXPECT_EQ(config.source.log_path, dir_.path() + "/robot.log");
  EXPECT_DOUBLE_EQ(config.source.speed, 1.0);
  EXPECT_EQ(config.upload.uploader.max_batch_items, 16);
  EXPECT_DOUBLE_EQ(config.upload.uploader.backoff.max, 5.0);
  EXPECT_DOUBLE_EQ(config.upload.trajectory_period, 2.0);
  EXPECT_EQ(config.map.file, dir_.path() + "/global");
  EXPECT_DOUBLE_EQ(config.status_period, 1.0);
}

TEST_F(AgentConfigTest, StartPoseIsOptionalAndSpeedHasForms) {
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(Parse(With("  start_pose: {x: 1.5, y: -2, theta: 0.5}\n", ""), &config, &error))
      << error;
  EXPECT_FALSE(config.start_pose.has_value());
  ASSERT_TRUE(Parse(With("speed: realtime", "speed: max"), &config, &error)) << error;
  EXPECT_DOUBLE_EQ(config.source.speed, 0.0);
  ASSERT_TRUE(Parse(With("speed: realtime", "speed: 4"), &config, &error)) << error;
  EXPECT_DOUBLE_EQ(config.source.speed, 4.0);
}

TEST_F(AgentConfigTest, SimulatorSource) {
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(Parse(With("  carmen:\n    log: robot.log\n",
                         "  simulator:\n    scenario: department_3robots\n    robot: robot2\n"),
                    &config, &error))
      << error;
  EXPECT_EQ(config.source.type, SourceConfig::Type::kSimulator);
  EXPECT_EQ(config.source.scenario, "department_3robots");
  EXPECT_EQ(config.source.sim_robot, "robot2");
}

struct BadCase {
  std::string from;
  std::string to;
  std::string expected;  // the message must contain this (the field, and why)
};

TEST_F(AgentConfigTest, EachBadFieldIsNamed) {
  const std::vector<BadCase> cases = {
      {"  id: r1\n", "", "robot.id: missing"},
      {"id: r1", "id: 'r 1/x'", "robot.id: must be 1-64 characters"},
      {"theta: 0.5}", "}", "robot.start_pose.theta: missing"},
      {"x: 1.5", "x: east", "robot.start_pose.x: must be a number"},
      {"address: 127.0.0.1:50051", "address: localhost", "server.address: must be host:port"},
      {"  path: r1-outbox.db\n", "", "outbox.path: missing"},
      {"algorithm: scan-matching", "algorithm: magic", "slam.algorithm: 'magic' is not"},
      {"resolution: 0.05", "resolution: -1", "slam.resolution: must be > 0, got -1"},
      {"submap_scans: 50", "submap_scans: many", "slam.submap_scans: must be a whole number"},
      {"log: robot.log", "log: missing.log", "source.carmen.log: no such file"},
      {"    log: robot.log\n", "", "source.carmen.log: missing"},
      {"speed: realtime", "speed: -2", "source.speed: must be 'max', 'realtime' or a factor"},
      {"  carmen:\n    log: robot.log\n", "", "source: give exactly one of"},
      {"  carmen:\n    log: robot.log\n", "  simulator:\n    scenario: x\n",
       "source.simulator.robot: missing"},
      {"batch_size: 16", "batch_size: 0", "upload.batch_size: must be in [1, 256]"},
      {"initial: 0.1", "initial: 0", "upload.backoff.initial: must be > 0"},
      {"multiplier: 2", "multiplier: 0.5", "upload.backoff.multiplier: must be >= 1"},
      {"max: 5", "max: 0.05", "upload.backoff.max: must be >= initial"},
      {"jitter: 0.1", "jitter: 2", "upload.backoff.jitter: must be in [0, 1]"},
      {"trajectory_period: 2", "trajectory_period: -1", "upload.trajectory_period: must be >= 0"},
      {"period: 1", "period: -5", "status.period: must be >= 0"},
      {"  period: 1\n", "  period: 1\n  colour: red\n", "status.colour: unknown field"},
      {"upload:", "uplaod:", "uplaod: unknown field"},
      {"map:\n  file: global", "map: [1, 2]", "map: must be a map"},
  };
  for (const BadCase& bad : cases) {
    AgentConfig config;
    std::string error;
    EXPECT_FALSE(Parse(With(bad.from, bad.to), &config, &error)) << bad.expected;
    EXPECT_THAT(error, HasSubstr(bad.expected)) << "case: " << bad.to;
    EXPECT_THAT(error, ::testing::StartsWith("robot.yaml: "));
  }
}

// The localization block: parsed with its map resolved against the file, and each bad field
// named. Base() places the robot (start_pose), which a map from the server must not have.
TEST_F(AgentConfigTest, LocalizationModeIsParsedAndItsBadFieldsAreNamed) {
  std::ofstream(dir_.path() + "/floor.yaml") << "image: floor.pgm\n";
  const std::string with_file =
      Base() +
      "localization:\n  enabled: true\n  map: floor.yaml\n  initial_pose: {x: 1, y: 2, "
      "theta: 0.5}\n  particles: 3000\n  beams: 90\n  seed: 4\n  scan_seeding: false\n  "
      "random_injection: true\n  "
      "share_detections: false\n";
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(Parse(with_file, &config, &error)) << error;
  const LocalizationConfig& localization = config.localization;
  EXPECT_TRUE(localization.enabled);
  EXPECT_EQ(localization.map, dir_.path() + "/floor.yaml");
  ASSERT_TRUE(localization.initial_pose.has_value());
  EXPECT_DOUBLE_EQ(localization.initial_pose->rotation(), 0.5);
  EXPECT_EQ(localization.particles, 3000);
  EXPECT_EQ(localization.beams, 90);
  EXPECT_EQ(localization.seed, 4);
  EXPECT_FALSE(localization.scan_seeding);
  EXPECT_TRUE(localization.random_injection);
  EXPECT_FALSE(localization.share_detections);

  const std::vector<std::pair<std::string, std::string>> cases = {
      {"localization: {enabled: true, map: nowhere.yaml}", "localization.map: no such file"},
      {"localization: {enabled: true}", "robot.start_pose: must be left out when localizing"},
      {"localization: {enabled: true, map: floor.yaml, particles: 5}",
       "localization.particles: must be in [10, 1000000], got 5"},
      {"localization: {enabled: true, map: floor.yaml, beams: 0}",
       "localization.beams: must be in [1, 10000]"},
      {"localization: {enabled: true, map: floor.yaml, initial_pose: {x: 1, y: 2}}",
       "localization.initial_pose.theta: missing"},
      {"localization: {enabled: true, map: floor.yaml, initial_position_std: 0}",
       "localization.initial_position_std: must be > 0"},
      {"localization: {enabled: true, map: floor.yaml, map_wait: -1}",
       "localization.map_wait: must be > 0"},
      {"localization: {enabled: true, map: floor.yaml, partciles: 5}",
       "localization.partciles: unknown field"},
  };
  for (const auto& [block, expected] : cases) {
    EXPECT_FALSE(Parse(Base() + block + "\n", &config, &error)) << expected;
    EXPECT_THAT(error, HasSubstr(expected)) << block;
  }
  // The server's map: no start pose (its frame is the global one), and map.subscribe on.
  std::string unplaced = With("  start_pose: {x: 1.5, y: -2, theta: 0.5}\n", "");
  EXPECT_TRUE(Parse(unplaced + "localization: {enabled: true}\n", &config, &error)) << error;
  EXPECT_TRUE(config.localization.map.empty());
  std::string no_subscribe = unplaced;
  no_subscribe.replace(no_subscribe.find("  file: global"), 14, "  subscribe: false");
  EXPECT_FALSE(Parse(no_subscribe + "localization: {enabled: true}\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("localization.map: missing, and map.subscribe is false"));
}

TEST_F(AgentConfigTest, SourceIsRequired) {
  AgentConfig config;
  std::string error;
  const std::string text = "robot: {id: r1}\noutbox: {path: x.db}\n";
  EXPECT_FALSE(Parse(text, &config, &error));
  EXPECT_THAT(error, HasSubstr("source: missing"));
}

TEST_F(AgentConfigTest, BrokenYamlAndMissingFile) {
  AgentConfig config;
  std::string error;
  EXPECT_FALSE(Parse("robot: {id: r1\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("robot.yaml: not valid YAML"));
  EXPECT_FALSE(Parse("- a\n- b\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("expected a map"));
  EXPECT_FALSE(LoadAgentConfig(dir_.path() + "/absent.yaml", &config, &error));
  EXPECT_THAT(error, HasSubstr("absent.yaml: cannot read"));
}

TEST_F(AgentConfigTest, LoadResolvesPathsAgainstTheFile) {
  const std::string path = dir_.path() + "/robot.yaml";
  std::ofstream(path) << Base();
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(LoadAgentConfig(path, &config, &error)) << error;
  EXPECT_EQ(config.source.log_path, dir_.path() + "/robot.log");
}

}  // namespace
}  // namespace fleetmap

namespace fleetmap {
namespace {

TEST(ShippedAgentConfigTest, TheExampleConfigurationLoads) {
  const std::string path =
      std::string(FLEETMAP_AGENT_TEST_SOURCE_DIR) + "/robot_agent/agent/robot.example.yaml";
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(LoadAgentConfig(path, &config, &error)) << error;
  EXPECT_EQ(config.robot_id, "robot1");
  EXPECT_EQ(config.source.type, SourceConfig::Type::kSimulator);
  EXPECT_FALSE(config.start_pose.has_value());
}

}  // namespace
}  // namespace fleetmap

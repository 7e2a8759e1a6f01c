// The fleetmap-agent binary in localization mode (Monte Carlo localization in a known map), end
// to end: one agent maps the synthetic log into a real server, then agents on the same drive
// localize in the server's global map and in a map file, and their uploaded poses are checked
// against the truth in the global frame.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "robot_agent/agent/proto_conversions.h"
#include "shared/codec/grid_codec.h"
#include "shared/io/map_file.h"
#include "tests/agent/child_process.h"
#include "tests/agent/synthetic_drive.h"
#include "tests/agent/test_server.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::ChildProcess;
using ::testing::HasSubstr;

constexpr int kScans = 300;

std::string AgentBinary() {
  const std::string dir = std::getenv("FLEETMAP_BINARY_DIR")
                              ? testing::BinaryDir()
                              : std::string(FLEETMAP_AGENT_TEST_BINARY_DIR);
  return dir + "/robot_agent/agent/fleetmap-agent";
}

class AgentLocalizationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(AgentBinary())) {
      GTEST_SKIP() << "fleetmap-agent not built (" << AgentBinary() << ")";
    }
    ASSERT_TRUE(testing::WriteSyntheticLog(dir_.path() + "/drive.log", kScans));
    server_ = testing::StartServer(0, dir_.path() + "/server.db");
    ASSERT_NE(server_, nullptr);
  }

  // A configuration on the synthetic log; `robot` and `extra` complete it.
  std::string WriteConfig(const std::string& id, const std::string& robot_extra,
                          const std::string& extra) {
    const std::string path = dir_.path() + "/" + id + ".yaml";
    std::ofstream(path) << "robot: {id: " << id << robot_extra << "}\n"
                        << "server: {address: 127.0.0.1:" << server_->port() << "}\n"
                        << "outbox: {path: " << id << "-outbox.db}\n"
                        << "slam: {submap_scans: 40}\n"
                        << "source: {carmen: {log: drive.log}, speed: max}\n"
                        << "upload: {backoff: {initial: 0.05, max: 0.3}, drain_timeout: 60}\n"
                        << "map: {reconnect: {initial: 0.05, max: 0.3}}\n"
                        << "status: {period: 0.5}\n"
                        << extra;
    return path;
  }

  std::optional<int> Run(const std::string& config, const std::string& name, std::string* output) {
    ChildProcess agent(AgentBinary(), {"--config", config}, dir_.path() + "/" + name + ".out");
    const std::optional<int> code = agent.Wait(180.0);
    *output = agent.Output();
    return code;
  }

  v1::GetRobotsResponse Robots() {
    auto stub = v1::MapService::NewStub(grpc::CreateChannel(
        "127.0.0.1:" + std::to_string(server_->port()), grpc::InsecureChannelCredentials()));
    grpc::ClientContext context;
    v1::GetRobotsResponse robots;
    EXPECT_TRUE(stub->GetRobots(&context, v1::GetRobotsRequest(), &robots).ok());
    return robots;
  }

  // The mapper started unplaced, as robots usually do; being the first to send a submap, it
  // defines the global frame (up to what the pose graph moves it by).
  Rigid2d MapperInGlobal() {
    const v1::GetRobotsResponse robots = Robots();
    for (const v1::RobotInfo& robot : robots.robots()) {
      if (robot.robot_id() != "mapper") continue;
      EXPECT_EQ(robot.placement().source(), "reference") << robot.placement().note();
      return agent::FromProto(robot.placement().local_in_global());
    }
    ADD_FAILURE() << "no robot \"mapper\" on the server";
    return Rigid2d();
  }

  // Maps the drive as robot "mapper" and waits for a global map.
  void MapTheRoom() {
    std::string output;
    ASSERT_EQ(Run(WriteConfig("mapper", "", ""), "mapper", &output), std::optional<int>(0))
        << output;
    for (int i = 0; i < 300 && !GlobalMap(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(GlobalMap().has_value()) << "no global map from the mapper";
  }

  std::optional<OccupancyGrid> GlobalMap() {
    auto stub = v1::MapService::NewStub(grpc::CreateChannel(
        "127.0.0.1:" + std::to_string(server_->port()), grpc::InsecureChannelCredentials()));
    grpc::ClientContext context;
    v1::GlobalMap map;
    if (!stub->GetGlobalMap(&context, v1::GetGlobalMapRequest(), &map).ok() || !map.has_grid()) {
      return std::nullopt;
    }
    OccupancyGrid grid;
    GridDecodeError code;
    std::string error;
    if (!DecodeGrid(agent::FromProto(map.grid()), GridLimits(), OccupancyGridOptions(), &grid,
                    &code, &error)) {
      return std::nullopt;
    }
    return grid;
  }

  // The localizing robot's uploaded poses against the truth in the global frame, from scan
  // `from` on.
  struct Errors {
    double worst_position = 1e9, worst_heading = 1e9;  // metres, radians
    double mean_position = 1e9, mean_heading = 1e9;
  };
  Errors PoseErrors(const std::string& id, size_t from) {
    const std::optional<TrajectoryRecord> uploaded = server_->store()->LatestTrajectory(id);
    EXPECT_TRUE(uploaded.has_value());
    if (!uploaded) return {};
    EXPECT_EQ(uploaded->poses.size(), static_cast<size_t>(kScans)) << "one pose per scan";
    std::vector<Rigid2d> truth;
    // The mapper's local frame is where its scan poses are true.
    const Rigid2d mapper_in_global = MapperInGlobal();
    for (const SensorEvent& event : testing::SyntheticDrive(kScans)) {
      if (event.laser) truth.push_back(mapper_in_global * event.laser->robot_pose);
    }
    Errors errors{0.0, 0.0, 0.0, 0.0};
    int n = 0;
    for (size_t i = from; i < std::min(truth.size(), uploaded->poses.size()); ++i, ++n) {
      const Rigid2d& pose = uploaded->poses[i].pose;
      const double position = (pose.translation() - truth[i].translation()).norm();
      const double heading = std::abs(NormalizeAngle(pose.rotation() - truth[i].rotation()));
      errors.worst_position = std::max(errors.worst_position, position);
      errors.worst_heading = std::max(errors.worst_heading, heading);
      errors.mean_position += position;
      errors.mean_heading += heading;
    }
    errors.mean_position /= std::max(n, 1);
    errors.mean_heading /= std::max(n, 1);
    std::printf("%s: over scans %zu-%d: mean error %.3f m, %.2f deg; worst %.3f m, %.2f deg\n",
                id.c_str(), from, kScans - 1, errors.mean_position,
                errors.mean_heading * 180.0 / M_PI, errors.worst_position,
                errors.worst_heading * 180.0 / M_PI);
    return errors;
  }

  // Exact odometry and ranges: what is left is the map's error and the filter's spread.
  static void ExpectAccurate(const Errors& errors) {
    EXPECT_LT(errors.mean_position, 0.05);
    EXPECT_LT(errors.mean_heading, 0.02);
    EXPECT_LT(errors.worst_position, 0.15);
    EXPECT_LT(errors.worst_heading, 0.07);
  }

  const testing::ScopedTempDir dir_{"agent_localization"};
  std::unique_ptr<MapServer> server_;
};

TEST_F(AgentLocalizationTest, LocalizesInTheServersMapAndInAMapFileAndUploadsGlobalPoses) {
  ASSERT_NO_FATAL_FAILURE(MapTheRoom());

  // 1. In the server's global map, from a start pose known to 0.2 m / 0.1 rad. Registering a
  // robot whose frame is the global one must not disturb the merge of the unplaced mapper.
  const Rigid2d start = MapperInGlobal() * Rigid2d(0.15, -0.1, 0.08);
  std::string output;
  const std::string known = "localization: {enabled: true, particles: 2000, initial_pose: {x: " +
                            std::to_string(start.x()) + ", y: " + std::to_string(start.y()) +
                            ", theta: " + std::to_string(start.rotation()) + "}}\n";
  ASSERT_EQ(Run(WriteConfig("tracker", "", known), "tracker", &output), std::optional<int>(0))
      << output;
  EXPECT_THAT(output, HasSubstr("localization (MCL) in the server's global map"));
  EXPECT_THAT(output, HasSubstr("localization: map version"));
  EXPECT_THAT(output,
              ::testing::ContainsRegex("\\| MCL converged \\(std 0\\.[0-9] m\\) in map v[1-9]"));
  EXPECT_THAT(output, HasSubstr("scans=300 submaps queued=0"));
  EXPECT_THAT(output, HasSubstr("rejected=0"));
  ExpectAccurate(PoseErrors("tracker", 10));

  // The server places the robot in the global frame as it is (identity) with no submaps.
  bool found = false;
  const v1::GetRobotsResponse robots = Robots();
  for (const v1::RobotInfo& robot : robots.robots()) {
    if (robot.robot_id() != "tracker") continue;
    found = true;
    EXPECT_EQ(robot.submap_count(), 0);
    EXPECT_TRUE(robot.placement().placed());
    EXPECT_EQ(robot.placement().source(), "localization");
    EXPECT_NEAR(robot.placement().local_in_global().x(), 0.0, 1e-9);
    EXPECT_NEAR(robot.placement().local_in_global().theta(), 0.0, 1e-9);
  }
  EXPECT_TRUE(found);

  // 2. In a map file (the global map, as `fleetmapctl export` writes it), from nowhere: global
  // localization over the whole room.
  const std::optional<OccupancyGrid> map = GlobalMap();
  ASSERT_TRUE(map.has_value());
  std::string error;
  ASSERT_TRUE(WriteMap(dir_.path() + "/room", *map, &error)) << error;
  const std::string lost =
      "map: {subscribe: false}\n"
      "localization: {enabled: true, map: room.yaml, particles: 5000}\n";
  ASSERT_EQ(Run(WriteConfig("lost", "", lost), "lost", &output), std::optional<int>(0)) << output;
  EXPECT_THAT(output, HasSubstr("localization (MCL) in " + dir_.path() + "/room.yaml"));
  EXPECT_THAT(output, HasSubstr("first converged after"));
  EXPECT_THAT(output, HasSubstr("| MCL converged (std"));
  EXPECT_THAT(output, HasSubstr("global start not confirmed by a detection"));
  ExpectAccurate(PoseErrors("lost", 200));
}

TEST_F(AgentLocalizationTest, WithoutAMapFromTheServerItStopsAndSaysWhatToDo) {
  std::string output;
  const std::string config =
      WriteConfig("waiting", "", "localization: {enabled: true, map_wait: 1}\n");
  EXPECT_EQ(Run(config, "waiting", &output), std::optional<int>(1)) << output;
  EXPECT_THAT(output, HasSubstr("no global map from the server within"));
  EXPECT_THAT(output, HasSubstr("give localization.map a map file"));
}

TEST_F(AgentLocalizationTest, AMissingMapFileIsRefusedNamingTheField) {
  std::string output;
  const std::string config =
      WriteConfig("nofile", "", "localization: {enabled: true, map: nowhere.yaml}\n");
  EXPECT_EQ(Run(config, "nofile", &output), std::optional<int>(1)) << output;
  EXPECT_THAT(output, HasSubstr("localization.map: no such file"));
}

}  // namespace
}  // namespace fleetmap

// The fleetmap-agent binary end to end on a generated CARMEN log: against a fleetmap-server
// process (merged map checked against the ground truth), and against the server library in
// this process for restart, outage and signal tests that count what the store holds.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "robot_agent/agent/proto_conversions.h"
#include "shared/codec/grid_codec.h"
#include "tests/agent/child_process.h"
#include "tests/agent/synthetic_drive.h"
#include "tests/agent/test_server.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::ChildProcess;
using ::testing::HasSubstr;

const Rigid2d kStartPose(10.0, 20.0, 0.5);  // the robot's local map frame in the global frame
constexpr int kScans = 300;                 // 30 s of driving, 30 m

// FLEETMAP_BINARY_DIR when set (e.g. an installed tree), else this build.
std::string BinaryDir() {
  return std::getenv("FLEETMAP_BINARY_DIR") ? testing::BinaryDir()
                                            : std::string(FLEETMAP_AGENT_TEST_BINARY_DIR);
}
std::string AgentBinary() { return BinaryDir() + "/robot_agent/agent/fleetmap-agent"; }
std::string ServerBinary() { return BinaryDir() + "/map_server/server/fleetmap-server"; }

class AgentBinaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(AgentBinary())) {
      GTEST_SKIP() << "fleetmap-agent not built (binary dir " << BinaryDir() << ")";
    }
    log_ = dir_.path() + "/drive.log";
    ASSERT_TRUE(testing::WriteSyntheticLog(log_, kScans));
  }

  // A configuration for the generated log; `extra` is appended (more sections).
  std::string WriteConfig(int port, const std::string& speed = "max",
                          const std::string& extra = "",
                          const std::string& algorithm = "scan-matching") {
    const std::string path = dir_.path() + "/robot.yaml";
    std::ofstream(path) << "robot: {id: r1, name: e2e robot, start_pose: {x: " << kStartPose.x()
                        << ", y: " << kStartPose.y() << ", theta: " << kStartPose.rotation()
                        << "}}\n"
                        << "server: {address: 127.0.0.1:" << port << "}\n"
                        << "outbox: {path: outbox.db}\n"
                        << "slam: {algorithm: " << algorithm << ", submap_scans: 40}\n"
                        << "source: {carmen: {log: drive.log}, speed: " << speed << "}\n"
                        << "upload: {backoff: {initial: 0.05, max: 0.3}, drain_timeout: 60, "
                           "flush_timeout: 3}\n"
                        << "map: {file: global, reconnect: {initial: 0.05, max: 0.3}}\n"
                        << "status: {period: 0.5}\n"
                        << extra;
    return path;
  }

  std::unique_ptr<ChildProcess> RunAgent(const std::string& config, const std::string& name,
                                         bool stay = false) {
    std::vector<std::string> args = {"--config", config};
    if (stay) args.push_back("--stay");
    return std::make_unique<ChildProcess>(AgentBinary(), args, dir_.path() + "/" + name + ".out");
  }

  void MapsTheLogAndTheMergedMapMatchesTheTruth(const std::string& algorithm, int min_submaps);

  const testing::ScopedTempDir dir_{"agent_e2e"};  // outlives the processes of each test
  std::string log_;
};

std::unique_ptr<v1::MapService::Stub> Stub(int port) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(256 << 20);
  return v1::MapService::NewStub(grpc::CreateCustomChannel(
      "127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials(), args));
}

// How well a global map matches the synthetic room placed at kStartPose: the fraction of wall
// points seen as occupied, and the fraction of occupied cells that lie on a wall.
struct MapScore {
  double walls_seen = 0.0;
  double occupied_on_walls = 0.0;
  int64_t occupied = 0;
};

double DistanceToWalls(const testing::SegmentWorld& world, const Eigen::Vector2d& point) {
  double best = 1e9;
  for (const testing::Segment& segment : world) {
    const Eigen::Vector2d ab = segment.b - segment.a;
    const double t = std::clamp((point - segment.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (segment.a + t * ab - point).norm());
  }
  return best;
}

MapScore ScoreMap(const QuantizedGrid& grid) {
  const testing::SegmentWorld room = testing::SyntheticRoom();
  const GridGeometry& g = grid.geometry;
  auto occupied_near = [&](const Eigen::Vector2d& global) {
    const int cx = static_cast<int>(std::floor((global.x() - g.origin.x()) / g.resolution));
    const int cy = static_cast<int>(std::floor((global.y() - g.origin.y()) / g.resolution));
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        const int x = cx + dx, y = cy + dy;
        if (x < 0 || y < 0 || x >= g.width || y >= g.height) continue;
        if (grid.cells[static_cast<size_t>(y) * g.width + x] > 0) return true;
      }
    }
    return false;
  };
  MapScore score;
  // The outer walls (the first four segments), sampled every 10 cm.
  int samples = 0, seen = 0;
  for (int i = 0; i < 4; ++i) {
    const testing::Segment& wall = room[static_cast<size_t>(i)];
    const int n = static_cast<int>((wall.b - wall.a).norm() / 0.1);
    for (int k = 1; k < n; ++k) {
      const Eigen::Vector2d local = wall.a + (wall.b - wall.a) * (static_cast<double>(k) / n);
      ++samples;
      if (occupied_near(kStartPose * local)) ++seen;
    }
  }
  score.walls_seen = static_cast<double>(seen) / samples;
  int64_t on_walls = 0;
  const Rigid2d global_to_local = kStartPose.inverse();
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      if (grid.cells[static_cast<size_t>(y) * g.width + x] <= 0) continue;
      ++score.occupied;
      const Eigen::Vector2d global = g.origin + Eigen::Vector2d(x + 0.5, y + 0.5) * g.resolution;
      if (DistanceToWalls(room, global_to_local * global) < 0.15) ++on_walls;
    }
  }
  score.occupied_on_walls =
      score.occupied > 0 ? static_cast<double>(on_walls) / score.occupied : 0.0;
  return score;
}

// The agent maps the log with `algorithm` into a real server process, and the merged map
// matches the synthetic room.
void AgentBinaryTest::MapsTheLogAndTheMergedMapMatchesTheTruth(const std::string& algorithm,
                                                                int min_submaps) {
  ChildProcess server(ServerBinary(),
                      {"--db", dir_.path() + "/server.db", "--listen", "127.0.0.1:0", "--port-file",
                       dir_.path() + "/port"},
                      dir_.path() + "/server.out");
  int port = 0;
  for (int i = 0; i < 500 && port == 0; ++i) {
    port = std::atoi(testing::ReadFile(dir_.path() + "/port").c_str());
    if (port == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GT(port, 0) << server.Output();

  // --stay: the agent keeps following the global map after the log ends, until SIGTERM.
  auto agent = RunAgent(WriteConfig(port, "max", "", algorithm), "agent", /*stay=*/true);
  for (int i = 0; i < 600; ++i) {
    if (agent->Output().find("staying until") != std::string::npos &&
        std::filesystem::exists(dir_.path() + "/global.pgm")) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  // The agent keeps the newest global map it follows.
  EXPECT_TRUE(std::filesystem::exists(dir_.path() + "/global.pgm")) << agent->Output();
  agent->Signal(SIGTERM);
  const std::optional<int> code = agent->Wait(60.0);
  ASSERT_TRUE(code.has_value()) << agent->Output();
  EXPECT_EQ(*code, 0) << agent->Output();
  const std::string output = agent->Output();
  EXPECT_THAT(output, HasSubstr("scans=300"));
  EXPECT_THAT(output, HasSubstr("server connected"));
  EXPECT_THAT(output, HasSubstr("rejected=0"));
  EXPECT_THAT(output, HasSubstr("pending=0 | trajectories"));
  EXPECT_THAT(output, ::testing::ContainsRegex("map (not )?streaming v[1-9]"));

  auto stub = Stub(port);
  grpc::ClientContext robots_context;
  v1::GetRobotsResponse robots;
  ASSERT_TRUE(stub->GetRobots(&robots_context, v1::GetRobotsRequest(), &robots).ok());
  ASSERT_EQ(robots.robots_size(), 1);
  EXPECT_EQ(robots.robots(0).robot_id(), "r1");
  EXPECT_GE(robots.robots(0).submap_count(), min_submaps);
  // Trajectory revisions are (backend revision << 32) + pose count: one pose per scan.
  EXPECT_EQ(robots.robots(0).trajectory_revision() & 0xffffffffLL, kScans) << "one pose per scan";
  EXPECT_TRUE(robots.robots(0).placement().placed());

  // The merge folds uploads into versions shortly after they arrive: wait for one that holds
  // the whole room.
  MapScore score;
  for (int attempt = 0; attempt < 100; ++attempt) {
    grpc::ClientContext context;
    v1::GlobalMap map;
    if (stub->GetGlobalMap(&context, v1::GetGlobalMapRequest(), &map).ok()) {
      QuantizedGrid grid;
      GridDecodeError code_ignored;
      std::string error;
      ASSERT_TRUE(
          Decompress(agent::FromProto(map.grid()), GridLimits(), &grid, &code_ignored, &error))
          << error;
      score = ScoreMap(grid);
      if (score.walls_seen > 0.9) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::printf(
      "merged map vs ground truth: %.1f %% of wall points occupied, %.1f %% of %lld "
      "occupied cells within 0.15 m of a wall\n",
      100.0 * score.walls_seen, 100.0 * score.occupied_on_walls,
      static_cast<long long>(score.occupied));
  EXPECT_GT(score.walls_seen, 0.9);
  EXPECT_GT(score.occupied_on_walls, 0.9) << score.occupied << " occupied cells";
  server.Signal(SIGTERM);
  EXPECT_EQ(server.Wait(30.0), std::optional<int>(0)) << server.Output();
}

TEST_F(AgentBinaryTest, MapsALogIntoTheServerProcessAndTheMergedMapMatchesTheTruth) {
  if (!std::filesystem::exists(ServerBinary())) {
    GTEST_SKIP() << "fleetmap-server not built yet (" << ServerBinary() << ")";
  }
  MapsTheLogAndTheMergedMapMatchesTheTruth("scan-matching", 5);  // 300 scans, 40 per submap
}

// The same through the RBPF backend (its submaps are groups of 10 keyframes a metre apart).
TEST_F(AgentBinaryTest, MapsALogWithTheRbpfBackend) {
  if (!std::filesystem::exists(ServerBinary())) {
    GTEST_SKIP() << "fleetmap-server not built yet (" << ServerBinary() << ")";
  }
  MapsTheLogAndTheMergedMapMatchesTheTruth("rbpf", 1);
}

TEST_F(AgentBinaryTest, RestartedAgentDuplicatesNothing) {
  auto server = testing::StartServer(0, dir_.path() + "/server.db");
  ASSERT_NE(server, nullptr);
  const std::string config = WriteConfig(server->port());
  auto first = RunAgent(config, "first");
  ASSERT_EQ(first->Wait(120.0), std::optional<int>(0)) << first->Output();
  const int64_t submaps = server->store()->CountSubmapRevisions("r1");
  const int64_t ids = server->store()->CountSubmapIds("r1");
  EXPECT_GE(ids, 5);
  // The same robot runs again over the same data (e.g. after a crash): same keys, nothing new.
  auto second = RunAgent(config, "second");
  ASSERT_EQ(second->Wait(120.0), std::optional<int>(0)) << second->Output();
  EXPECT_EQ(server->store()->CountSubmapRevisions("r1"), submaps);
  EXPECT_EQ(server->store()->CountSubmapIds("r1"), ids);
  EXPECT_THAT(second->Output(), HasSubstr("rejected=0"));
  EXPECT_EQ(server->store()->LatestTrajectory("r1")->poses.size(), static_cast<size_t>(kScans));
}

TEST_F(AgentBinaryTest, ServerUnavailableThenBackDrainsEverythingOnce) {
  int port;
  {
    auto probe = testing::StartServer(0);
    ASSERT_NE(probe, nullptr);
    port = probe->port();
  }
  // The agent maps the whole log while no server listens.
  auto agent = RunAgent(WriteConfig(port), "agent");
  std::this_thread::sleep_for(std::chrono::seconds(3));
  EXPECT_FALSE(agent->Wait(0.0).has_value()) << agent->Output();
  EXPECT_THAT(agent->Output(), HasSubstr("server disconnected"));
  auto server = testing::RestartServer(port, dir_.path() + "/server.db");
  ASSERT_NE(server, nullptr);
  ASSERT_EQ(agent->Wait(120.0), std::optional<int>(0)) << agent->Output();
  const std::string output = agent->Output();
  EXPECT_THAT(output, HasSubstr("scans=300"));
  const int64_t ids = server->store()->CountSubmapIds("r1");
  EXPECT_GE(ids, 5);
  EXPECT_EQ(server->store()->CountSubmapRevisions("r1"), ids) << "each submap stored once";
  EXPECT_EQ(server->store()->LatestTrajectory("r1")->poses.size(), static_cast<size_t>(kScans));
}

TEST_F(AgentBinaryTest, SigintFlushesAndExitsZeroAndARerunCompletesTheMap) {
  auto server = testing::StartServer(0, dir_.path() + "/server.db");
  ASSERT_NE(server, nullptr);
  // Real time: 30 s of data; interrupted after about 3.
  auto agent = RunAgent(WriteConfig(server->port(), "realtime"), "agent");
  std::this_thread::sleep_for(std::chrono::seconds(3));
  agent->Signal(SIGINT);
  ASSERT_EQ(agent->Wait(60.0), std::optional<int>(0)) << agent->Output();
  EXPECT_THAT(agent->Output(), HasSubstr("SIGINT received"));
  EXPECT_THAT(agent->Output(), HasSubstr("stopping: flushing"));
  const int64_t partial = server->store()->CountSubmapIds("r1");
  // The interrupted run finished its active submap and sent it.
  EXPECT_GE(partial, 1);
  auto rerun = RunAgent(WriteConfig(server->port()), "rerun");
  ASSERT_EQ(rerun->Wait(120.0), std::optional<int>(0)) << rerun->Output();
  EXPECT_GT(server->store()->CountSubmapIds("r1"), partial);
}

TEST_F(AgentBinaryTest, BadConfigurationExitsOneNamingTheField) {
  const std::string config = WriteConfig(1, "max", "bogus: 1\n");
  auto agent = RunAgent(config, "agent");
  ASSERT_EQ(agent->Wait(30.0), std::optional<int>(1));
  EXPECT_THAT(agent->Output(), HasSubstr("bogus: unknown field"));
}

}  // namespace
}  // namespace fleetmap

// The merge end-to-end fixture: server and agent processes, waiting for the settled merge,
// checking it against the truth (merge_e2e_fixture.h).

#include "tests/merge_e2e/merge_e2e_fixture.h"

#include <grpcpp/grpcpp.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "map_server/server/conversions.h"
#include "robot_agent/sim/map_accuracy.h"
#include "shared/codec/grid_codec.h"
#include "tests/server/process_util.h"

namespace fleetmap {

using testing::E2eProcess;

void MergeE2eTest::SetUp() {
  build_ = testing::TestBuildDir();
  server_binary_ = build_ + "/map_server/server/fleetmap-server";
  agent_binary_ = build_ + "/robot_agent/agent/fleetmap-agent";
  std::string error;
  simulation_ = sim::Simulation::FromFile(ScenarioPath(), &error, false);
  ASSERT_TRUE(simulation_) << error;
}

bool MergeE2eTest::StartServer() {
  const std::string port_file = dir_ + "/port";
  std::remove(port_file.c_str());
  const std::string listen = "127.0.0.1:" + std::to_string(port_);
  std::vector<std::string> args{"--db",        dir_ + "/server.db", "--listen",           listen,
                                "--port-file", port_file,           "--version-interval", "0.3"};
  // The merge is checked after the server's rebuild once uploads settle (WaitAllPlaced): 5 s
  // of quiet rather than the default 30 keeps the test short.
  args.insert(args.end(), {"--settle-seconds", "5"});
  server_ = std::make_unique<E2eProcess>(server_binary_, args, dir_ + "/server.log");
  for (int i = 0; i < 500; ++i) {
    std::ifstream in(port_file);
    int port = 0;
    if (in >> port && port > 0) {
      port_ = port;
      stub_ = v1::MapService::NewStub(grpc::CreateChannel("127.0.0.1:" + std::to_string(port_),
                                                          grpc::InsecureChannelCredentials()));
      return true;
    }
    if (!server_->Running()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

std::unique_ptr<E2eProcess> MergeE2eTest::StartAgent(const std::string& robot,
                                                     const std::string& speed) {
  const std::string config = dir_ + "/" + robot + ".yaml";
  std::ofstream out(config);
  out << "robot: {id: " << robot << "}\n"
      << "server: {address: 127.0.0.1:" << port_ << "}\n"
      << "outbox: {path: " << dir_ << "/" << robot << "-outbox.db}\n"
      << "slam: {submap_scans: 30}\n"
      << "source:\n  simulator: {scenario: " << ScenarioPath() << ", robot: " << robot
      << ", camera: " << (Camera() ? "true" : "false") << "}\n  speed: " << speed << "\n"
      << "detection: {enabled: " << (Camera() ? "true" : "false") << "}\n"
      << "upload:\n  trajectory_period: 2\n"
      << "  backoff: {initial: 0.1, multiplier: 2, max: 0.5, jitter: 0.2}\n"
      << "  drain_timeout: 90\n"
      << "map: {subscribe: false}\nstatus: {period: 5}\n";
  out.close();
  return std::make_unique<E2eProcess>(agent_binary_, std::vector<std::string>{"--config", config},
                                      dir_ + "/" + robot + ".log");
}

bool MergeE2eTest::WaitAllPlaced(double seconds, v1::GetRobotsResponse* robots) {
  const auto now = [] { return std::chrono::steady_clock::now(); };
  const auto deadline = now() + std::chrono::duration<double>(seconds);
  int64_t version = -1;
  auto unchanged_since = now();
  while (now() < deadline) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
    v1::GetRobotsRequest request;
    robots->Clear();
    bool all = false;
    if (stub_->GetRobots(&context, request, robots).ok() &&
        robots->robots_size() == static_cast<int>(Robots().size())) {
      all = LatestVersionSettled();
      for (const auto& r : robots->robots()) all = all && r.placement().placed();
    }
    if (!all || robots->latest_version() != version) {
      version = all ? robots->latest_version() : -1;
      unchanged_since = now();
    } else if (now() - unchanged_since >= std::chrono::seconds(2)) {
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  return false;
}

bool MergeE2eTest::LatestVersionSettled() const {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  v1::VersionInfo latest;
  return stub_->GetVersion(&context, v1::GetVersionRequest(), &latest).ok() &&
         latest.provenance().trigger().rfind("uploads settled", 0) == 0;
}

std::string MergeE2eTest::Logs() const {
  std::string text = "--- server.log\n" + testing::ReadWholeFile(dir_ + "/server.log");
  for (const std::string& robot : Robots()) {
    text += "--- " + robot + ".log\n" + testing::ReadWholeFile(dir_ + "/" + robot + ".log");
  }
  return text;
}

void MergeE2eTest::PrintAlignments() const {
  std::istringstream log(testing::ReadWholeFile(dir_ + "/server.log"));
  for (std::string line; std::getline(log, line);) {
    if (line.find("alignment accepted") != std::string::npos ||
        line.find("alignment withdrawn") != std::string::npos ||
        line.find("uploads settled") != std::string::npos) {
      std::printf("%s\n", line.substr(0, 160).c_str());
    }
  }
}

void MergeE2eTest::CheckMerge(const v1::GetRobotsResponse& robots) {
  std::map<std::string, Rigid2d> local_in_global;
  for (const auto& r : robots.robots()) {
    ASSERT_TRUE(r.placement().has_start_in_global()) << r.DebugString();
    local_in_global[r.robot_id()] = FromProto(r.placement().start_in_global());
  }
  const std::vector<std::string> names = Robots();
  const std::vector<Rigid2d> starts = simulation_->TruePoses();
  ASSERT_EQ(starts.size(), names.size());
  for (size_t a = 0; a < names.size(); ++a) {
    for (size_t b = a + 1; b < names.size(); ++b) {
      const Rigid2d estimated =
          local_in_global.at(names[a]).inverse() * local_in_global.at(names[b]);
      const Rigid2d truth = starts[a].inverse() * starts[b];
      const Rigid2d diff = truth.inverse() * estimated;
      const double t = diff.translation().norm();
      const double r = std::abs(NormalizeAngle(diff.rotation()));
      std::printf("relative transform %s-%s: error %.3f m, %.3f deg\n", names[a].c_str(),
                  names[b].c_str(), t, r * 180.0 / M_PI);
      EXPECT_LT(t, Bounds().max_translation) << names[a] << "-" << names[b];
      EXPECT_LT(r, Bounds().max_rotation) << names[a] << "-" << names[b];
    }
  }
  grpc::ClientContext context;
  v1::GetGlobalMapRequest request;
  v1::GlobalMap map;
  ASSERT_TRUE(stub_->GetGlobalMap(&context, request, &map).ok());
  OccupancyGrid grid{OccupancyGridOptions()};
  GridDecodeError code;
  std::string error;
  ASSERT_TRUE(
      DecodeGrid(FromProto(map.grid()), GridLimits(), OccupancyGridOptions(), &grid, &code, &error))
      << error;
  const Rigid2d global_in_world = starts[0] * local_in_global.at(names[0]).inverse();
  const WallScore score =
      ScoreOnWalls(grid, global_in_world, sim::WorldWalls(simulation_->world()));
  ASSERT_GT(score.occupied, 500);
  const double accuracy = score.fraction();
  std::printf("merged map: %lld occupied cells, %.2f %% within 1 cell of a true wall\n",
              static_cast<long long>(score.occupied), 100.0 * accuracy);
  EXPECT_GE(accuracy, Bounds().min_map_accuracy);
  PrintAlignments();
  CheckCtlEvaluate(robots, local_in_global, starts);
}

void MergeE2eTest::CheckCtlEvaluate(v1::GetRobotsResponse robots,
                                    std::map<std::string, Rigid2d> start_in_global,
                                    const std::vector<Rigid2d>& starts) {
  const std::string manifest = dir_ + "/truth.yaml";
  const std::vector<std::string> names = Robots();
  {
    std::ofstream out(manifest);
    out.precision(17);
    out << "robots:\n";
    for (size_t i = 0; i < names.size(); ++i) {
      out << "  - name: " << names[i] << "\n    start: {x: " << starts[i].x()
          << ", y: " << starts[i].y() << ", theta: " << starts[i].rotation() << "}\n";
    }
  }
  const std::string args =
      "--server 127.0.0.1:" + std::to_string(port_) + " --json evaluate --ground-truth " + manifest;
  for (int attempt = 0; attempt < 3; ++attempt) {
    std::string output;
    ASSERT_EQ(testing::RunCtl(args, &output), 0) << output;
    grpc::ClientContext context;
    v1::GetRobotsResponse after;
    ASSERT_TRUE(stub_->GetRobots(&context, v1::GetRobotsRequest(), &after).ok());
    if (after.latest_version() != robots.latest_version()) {
      robots = after;
      for (const auto& r : robots.robots()) {
        start_in_global[r.robot_id()] = FromProto(r.placement().start_in_global());
      }
      continue;
    }
    for (size_t b = 1; b < names.size(); ++b) {
      const Rigid2d diff = (starts[0].inverse() * starts[b]).inverse() *
                           (start_in_global.at(names[0]).inverse() * start_in_global.at(names[b]));
      const std::string key = "\"robot\": \"" + names[b] + "\", \"translation_error_m\": ";
      const size_t at = output.find(key);
      ASSERT_NE(at, std::string::npos) << output;
      EXPECT_NEAR(std::stod(output.substr(at + key.size())), diff.translation().norm(), 1e-3)
          << output;
    }
    return;
  }
  FAIL() << "the server kept publishing new versions";
}

void MergeE2eTest::FinishAgentsAndWaitPlaced(std::vector<std::unique_ptr<E2eProcess>>* agents,
                                             v1::GetRobotsResponse* robots) {
  for (auto& agent : *agents) {
    const auto code = agent->Wait(60.0);
    ASSERT_TRUE(code.has_value()) << "agent did not finish\n" << Logs();
    EXPECT_EQ(*code, 0) << Logs();
  }
  // The settled rebuild comes once the engine as fed has nothing pending; with robots held
  // waiting (a join on matches alone on probation at the end of building_2robots) it keeps
  // searching, and under the suite's load that took 59 s of 60 (session 44).
  ASSERT_TRUE(WaitAllPlaced(120.0, robots)) << robots->DebugString() << Logs();
}

void MergeE2eTest::RunAndCheck() {
  ASSERT_TRUE(StartServer()) << Logs();
  std::vector<std::unique_ptr<E2eProcess>> agents;
  for (const std::string& robot : Robots()) agents.push_back(StartAgent(robot, "max"));
  v1::GetRobotsResponse robots;
  ASSERT_NO_FATAL_FAILURE(FinishAgentsAndWaitPlaced(&agents, &robots));
  CheckMerge(robots);
  server_->Signal(SIGTERM);
  EXPECT_EQ(server_->Wait(20.0), std::optional<int>(0)) << Logs();
}

void MergeE2eTest::RunWithServerRestartAndCheck() {
  ASSERT_TRUE(StartServer()) << Logs();
  std::vector<std::unique_ptr<E2eProcess>> agents;
  // Paced, so the server dies while the robots are still driving.
  for (const std::string& robot : Robots()) agents.push_back(StartAgent(robot, "4"));
  std::this_thread::sleep_for(std::chrono::seconds(4));
  server_->Signal(SIGKILL);
  ASSERT_EQ(server_->Wait(10.0), std::optional<int>(128 + SIGKILL));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  ASSERT_TRUE(StartServer()) << Logs();
  v1::GetRobotsResponse robots;
  ASSERT_NO_FATAL_FAILURE(FinishAgentsAndWaitPlaced(&agents, &robots));
  // Nothing lost: every submap the agents produced is stored (their outboxes drained).
  int64_t submaps = 0;
  for (const auto& r : robots.robots()) submaps += r.submap_count();
  EXPECT_GE(submaps, 6);
  CheckMerge(robots);
  server_->Signal(SIGTERM);
  EXPECT_EQ(server_->Wait(20.0), std::optional<int>(0)) << Logs();
}

}  // namespace fleetmap

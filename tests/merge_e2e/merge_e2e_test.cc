// End to end (issues 8 and 9): a real fleetmap-server (SQLite in a temp folder) and real
// fleetmap-agent processes (one per robot) on loopback drive a simulated scenario with unknown
// start poses; the server's merge engine must place every robot, without detections (east_end,
// the building) or with the cameras' (the demo's department). The robots' relative transforms
// are checked against the simulator's truth and the merged map against the world. Other cases
// kill the server (SIGKILL) mid-run and restart it.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "map_server/server/conversions.h"
#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "robot_agent/sim/map_accuracy.h"
#include "robot_agent/sim/simulation.h"
#include "shared/codec/grid_codec.h"
#include "tests/merge_e2e/merge_e2e_process.h"
#include "tests/server/process_util.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::E2eProcess;

// Bounds that catch a wrong or visibly displaced merge (an aliased one is metres or tens of
// degrees off), not the 3 cm / 0.3 deg target, which docs/BENCHMARKS.md measures.
struct MergeBounds {
  double max_translation;  // metres, relative transform of every pair of robots
  double max_rotation;     // radians
  double min_map_accuracy;  // occupied cells within 1 cell of a true wall
};

// Merging from submap matching alone, on a short scenario whose maps overlap early.
class MergeE2eTest : public ::testing::Test {
 protected:
  virtual std::string ScenarioPath() const {
    return testing::SourceDir() + "/tests/merge_e2e/east_end_3robots.yaml";
  }
  virtual bool Camera() const { return false; }
  virtual std::vector<std::string> Robots() const { return {"robot1", "robot2", "robot3"}; }
  // The pair bounds catch an aliased merge (metres or tens of degrees off) or a robot left
  // unplaced; the map bound, a map rendered wrong. Measured on 2026-12-06 (session 32), 9 runs
  // of both cases, 5 of them beside a benchmark: pairs 0.003-0.079 m / 0.008-0.176 deg, map
  // 83.0-94.3 % (were 0.2 m / 1 deg / 70 %; docs/BENCHMARKS.md, end-to-end).
  virtual MergeBounds Bounds() const { return {0.15, 0.0105, 0.75}; }

  void SetUp() override {
    build_ = testing::MergeE2eBuildDir();
    server_binary_ = build_ + "/map_server/server/fleetmap-server";
    agent_binary_ = build_ + "/robot_agent/agent/fleetmap-agent";
    std::string error;
    simulation_ = sim::Simulation::FromFile(ScenarioPath(), &error, false);
    ASSERT_TRUE(simulation_) << error;
  }

  // Starts the server; port 0 picks a free port (remembered for restarts).
  bool StartServer() {
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
        stub_ = v1::MapService::NewStub(grpc::CreateChannel(
            "127.0.0.1:" + std::to_string(port_), grpc::InsecureChannelCredentials()));
        return true;
      }
      if (!server_->Running()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  std::unique_ptr<E2eProcess> StartAgent(const std::string& robot, const std::string& speed) {
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

  // GetRobots until every robot is placed (and has all its submaps), or the timeout.
  // Every robot placed, the latest version the rebuild after the uploads settled, and no new
  // version for 2 s: the agents' outboxes are drained before this is called, so the worker has
  // folded in all they sent. The joins made as uploads came in depend on their order (on
  // 2026-12-07 CI, of session 39's commits, left robot2 waiting: its join withdrawn as the maps
  // grew, a half-turned alternative 0.3 m away as consistent over a third of the overlap); the
  // rebuild replays the store at once, as the demo's launcher sees it.
  bool WaitAllPlaced(double seconds, v1::GetRobotsResponse* robots) {
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

  // The latest version is the server's rebuild once the uploads settled (or its note that the
  // merge as fed is kept): the map checked no longer depends on the order uploads came in.
  bool LatestVersionSettled() const {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
    v1::VersionInfo latest;
    return stub_->GetVersion(&context, v1::GetVersionRequest(), &latest).ok() &&
           latest.provenance().trigger().rfind("uploads settled", 0) == 0;
  }

  std::string Logs() const {
    std::string text = "--- server.log\n" + testing::ReadWholeFile(dir_ + "/server.log");
    for (const std::string& robot : Robots()) {
      text += "--- " + robot + ".log\n" + testing::ReadWholeFile(dir_ + "/" + robot + ".log");
    }
    return text;
  }

  // The server's log lines saying how each robot was placed (and any join undone), so a
  // passing run's output tells which evidence merged the map.
  void PrintAlignments() const {
    std::istringstream log(testing::ReadWholeFile(dir_ + "/server.log"));
    for (std::string line; std::getline(log, line);) {
      if (line.find("alignment accepted") != std::string::npos ||
          line.find("alignment withdrawn") != std::string::npos ||
          line.find("uploads settled") != std::string::npos) {
        std::printf("%s\n", line.substr(0, 160).c_str());
      }
    }
  }

  // Relative transforms against the truth (each robot's local frame is its odometry frame, the
  // identity at its true start pose; the server places it where the robot's first submap puts
  // it) and the merged map against the world.
  void CheckMerge(const v1::GetRobotsResponse& robots) {
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
    ASSERT_TRUE(DecodeGrid(FromProto(map.grid()), GridLimits(), OccupancyGridOptions(), &grid,
                           &code, &error))
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

  // fleetmapctl evaluate, which scores the demo, reads the same relative transforms from the
  // server. The server may publish a newer version meanwhile (its settled rebuild): then the
  // transforms are read again.
  void CheckCtlEvaluate(v1::GetRobotsResponse robots,
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
    const std::string args = "--server 127.0.0.1:" + std::to_string(port_) +
                             " --json evaluate --ground-truth " + manifest;
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
        const Rigid2d diff =
            (starts[0].inverse() * starts[b]).inverse() *
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

  // Every agent exits 0 (its outbox drained), then the server places every robot.
  void FinishAgentsAndWaitPlaced(std::vector<std::unique_ptr<E2eProcess>>* agents,
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

  // Server + one agent per robot at full speed; every robot placed and the merge within bounds.
  void RunAndCheck() {
    ASSERT_TRUE(StartServer()) << Logs();
    std::vector<std::unique_ptr<E2eProcess>> agents;
    for (const std::string& robot : Robots()) agents.push_back(StartAgent(robot, "max"));
    v1::GetRobotsResponse robots;
    ASSERT_NO_FATAL_FAILURE(FinishAgentsAndWaitPlaced(&agents, &robots));
    CheckMerge(robots);
    server_->Signal(SIGTERM);
    EXPECT_EQ(server_->Wait(20.0), std::optional<int>(0)) << Logs();
  }

  // The same, paced, with the server SIGKILLed while the robots drive and restarted on the same
  // port and database: nothing is lost and the merge still holds. The wait for placements covers
  // the server's rebuild once uploads settle: the restarted server can be left with a join
  // waiting that the rebuild makes.
  void RunWithServerRestartAndCheck() {
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

  // First, so that it goes last: the server and the agents have stopped when it is removed.
  const testing::ScopedTempDir temp_{"merge_e2e"};
  const std::string dir_ = temp_.path();
  std::string build_, server_binary_, agent_binary_;
  int port_ = 0;
  std::unique_ptr<sim::Simulation> simulation_;
  std::unique_ptr<E2eProcess> server_;
  std::unique_ptr<v1::MapService::Stub> stub_;
};

// Without detections every robot is placed by submap matching alone. robot2 used to wait: its
// map turned half round fits robot1's nearly as well (the east end's corridors swap under that
// turn), and the whole-map check kept the join a hypothesis. That turned fit puts walls across
// corridors the other robot drove, and such an alternative no longer blocks the join
// (MergeEngineOptions::whole_map_min_contradictions). Measured on 2026-12-05 (session 21), 12
// runs while benchmarks kept both cores busy: every robot placed; pairs 0.018-0.103 m /
// 0.005-0.21 deg; map 82.3-96.2 % within 1 cell of a wall (robot1's start anchors it: 0.1 m
// between the robots is two cells). Since submaps are searched again as maps grow (session 23)
// robot2 is often placed by its early submaps, up to 0.78 deg off in 11 runs: the other robots'
// bodies, mapped where they passed it, turn those matches (the bound is 1 deg). On 2026-12-05
// (CI of session 29) robot1 was left waiting: the half-turned alternative crossed 29 walls
// against the join's 0, and 30 ruled one out then; 20 since session 30.
TEST_F(MergeE2eTest, AgentsWithUnknownStartsAreMergedByTheServer) { RunAndCheck(); }
// After the restart the server searched every stored submap over the maps of that moment, and
// left robot2 waiting in 2 of 16 runs until submaps are searched again once the other map has
// grown (MergeEngineOptions::cross_retry_growth). That needed a whole-map check examining more
// alternatives, which one search that keeps its frontier made cheap (PeakSearch): 11 of 11 runs
// passed on 2026-12-05 (session 23), 15-18 s each, robot2 up to 0.76 deg off the others
// (docs/BENCHMARKS.md, issue 8). In session 26 (every join's local constraints kept), 2 of 16
// runs left robot1 waiting after the restart: the turned-round alternative crossed 26 walls, not
// the 38 that rule it out. Both stores, replayed at once (as the settled rebuild does), place all
// three within 0.09 m / 0.16 deg, so this case now waits for that rebuild as well.
TEST_F(MergeE2eTest, ServerKilledAndRestartedMidRunLosesNothing) { RunWithServerRestartAndCheck(); }

// The demo's case (deploy/demo.sh): department_3robots, camera detection on, 159 s of simulated
// driving. Measured on 2026-12-04 (session 18), 4 runs of each case: pair errors 0.025-0.317 m /
// 0.003-0.443 deg (the largest between robot2 and robot3, whose starts are 40 m apart), map
// 85.8-92.8 % within 1 cell of a wall (session 4: 0.01-0.28 m / 0.01-0.44 deg, 85.5-96.3 %;
// docs/BENCHMARKS.md). On 2026-12-06 (session 32), 9 runs of both cases, 5 of them beside a
// benchmark: 0.027-0.109 m / 0.000-0.195 deg, map 91.9-97.3 %. The bounds (were 0.4 m / 1 deg /
// 80 %) leave room for that and catch an aliased merge (robot3 48.9 m / 180 deg off), a
// displaced one, or a robot left unplaced.
class DetectionMergeE2eTest : public MergeE2eTest {
 protected:
  std::string ScenarioPath() const override {
    return testing::SourceDir() + "/robot_agent/sim/scenarios/department_3robots.yaml";
  }
  bool Camera() const override { return true; }
  MergeBounds Bounds() const override { return {0.25, 0.0105, 0.85}; }
};

// At full speed robot2's map turned round sometimes matches robot3's (the department is nearly
// symmetric) before any of robot3's detections reach the server; session 2 had to disable this
// test for it (about 1 run in 12 placed robot3 48.8 m / 180 deg off). The merge engine now
// withdraws a join that later detections contradict (merge_engine_withdraw.cc) and the
// detections place robot3 again: 40 of 40 runs passed on 2026-12-01 (session 3), 5 of them
// through a withdrawal; pairs 0.08-0.50 m / 0.13-0.98 deg, map 66-76 %.
TEST_F(DetectionMergeE2eTest, AgentsWithUnknownStartsAreMergedByTheServer) { RunAndCheck(); }
TEST_F(DetectionMergeE2eTest, ServerKilledAndRestartedMidRunLosesNothing) { RunWithServerRestartAndCheck(); }

// The building without detections: every submap is a stretch of plain corridor or a room like
// the next, so no submap match is unambiguous, and the server merges the two robots on their
// whole maps (MergeEngineOptions::whole_map_matches, on since session 36). Measured on
// 2026-12-06 (session 36) through deploy/launch.sh: 0.038 m / 0.01 deg, map 100 %; on the
// in-process bench 0.010-0.045 m over 4 seeds. The bounds catch a robot left waiting or joined
// a corridor off.
class BuildingMergeE2eTest : public MergeE2eTest {
 protected:
  std::string ScenarioPath() const override {
    return testing::SourceDir() + "/robot_agent/sim/scenarios/building_2robots.yaml";
  }
  std::vector<std::string> Robots() const override { return {"robot1", "robot2"}; }
  MergeBounds Bounds() const override { return {0.15, 0.0105, 0.9}; }
};

TEST_F(BuildingMergeE2eTest, RobotsWithoutDetectionsAreMergedOnTheirWholeMaps) { RunAndCheck(); }

}  // namespace
}  // namespace fleetmap

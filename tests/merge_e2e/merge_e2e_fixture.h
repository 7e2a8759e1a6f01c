// The merge end to end (issues 8 and 9): the fixture that runs a real fleetmap-server and one
// fleetmap-agent process per robot on loopback, waits for the settled merge and checks it
// against the simulator's truth (merge_e2e_test.cc holds the cases).

#ifndef FLEETMAP_TESTS_MERGE_E2E_MERGE_E2E_FIXTURE_H_
#define FLEETMAP_TESTS_MERGE_E2E_MERGE_E2E_FIXTURE_H_

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "robot_agent/sim/simulation.h"
#include "shared/core/rigid2d.h"
#include "tests/merge_e2e/merge_e2e_process.h"
#include "tests/support/test_support.h"

namespace fleetmap {

// Bounds that catch a wrong or visibly displaced merge (an aliased one is metres or tens of
// degrees off), not the 3 cm / 0.3 deg target, which docs/BENCHMARKS.md measures.
struct MergeBounds {
  double max_translation;   // metres, relative transform of every pair of robots
  double max_rotation;      // radians
  double min_map_accuracy;  // occupied cells within 1 cell of a true wall
};

// Merging from submap matching alone, on a short scenario whose maps overlap early.
class MergeE2eTest : public ::testing::Test {
 protected:
  using E2eProcess = testing::E2eProcess;

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

  void SetUp() override;

  // Starts the server; port 0 picks a free port (remembered for restarts).
  bool StartServer();

  std::unique_ptr<E2eProcess> StartAgent(const std::string& robot, const std::string& speed);

  // GetRobots until every robot is placed (and has all its submaps), or the timeout.
  // Every robot placed, the latest version the rebuild after the uploads settled, and no new
  // version for 2 s: the agents' outboxes are drained before this is called, so the worker has
  // folded in all they sent. The joins made as uploads came in depend on their order (on
  // 2026-12-07 CI, of session 39's commits, left robot2 waiting: its join withdrawn as the maps
  // grew, a half-turned alternative 0.3 m away as consistent over a third of the overlap); the
  // rebuild replays the store at once, as the demo's launcher sees it.
  bool WaitAllPlaced(double seconds, v1::GetRobotsResponse* robots);

  // The latest version is the server's rebuild once the uploads settled (or its note that the
  // merge as fed is kept): the map checked no longer depends on the order uploads came in.
  bool LatestVersionSettled() const;

  std::string Logs() const;

  // The server's log lines saying how each robot was placed (and any join undone), so a
  // passing run's output tells which evidence merged the map.
  void PrintAlignments() const;

  // Relative transforms against the truth (each robot's local frame is its odometry frame, the
  // identity at its true start pose; the server places it where the robot's first submap puts
  // it) and the merged map against the world.
  void CheckMerge(const v1::GetRobotsResponse& robots);

  // fleetmapctl evaluate, which scores the demo, reads the same relative transforms from the
  // server. The server may publish a newer version meanwhile (its settled rebuild): then the
  // transforms are read again.
  void CheckCtlEvaluate(v1::GetRobotsResponse robots,
                        std::map<std::string, Rigid2d> start_in_global,
                        const std::vector<Rigid2d>& starts);

  // Every agent exits 0 (its outbox drained), then the server places every robot.
  void FinishAgentsAndWaitPlaced(std::vector<std::unique_ptr<E2eProcess>>* agents,
                                 v1::GetRobotsResponse* robots);

  // Server + one agent per robot at full speed; every robot placed and the merge within bounds.
  void RunAndCheck();

  // The same, paced, with the server SIGKILLed while the robots drive and restarted on the same
  // port and database: nothing is lost and the merge still holds. The wait for placements covers
  // the server's rebuild once uploads settle: the restarted server can be left with a join
  // waiting that the rebuild makes.
  void RunWithServerRestartAndCheck();

  // First, so that it goes last: the server and the agents have stopped when it is removed.
  const testing::ScopedTempDir temp_{"merge_e2e"};
  const std::string dir_ = temp_.path();
  std::string build_, server_binary_, agent_binary_;
  int port_ = 0;
  std::unique_ptr<sim::Simulation> simulation_;
  std::unique_ptr<E2eProcess> server_;
  std::unique_ptr<v1::MapService::Stub> stub_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_TESTS_MERGE_E2E_MERGE_E2E_FIXTURE_H_

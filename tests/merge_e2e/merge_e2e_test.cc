// End to end (issues 8 and 9): a real fleetmap-server (SQLite in a temp folder) and real
// fleetmap-agent processes (one per robot) on loopback drive a simulated scenario with unknown
// start poses; the server's merge engine must place every robot, without detections (east_end,
// the building) or with the cameras' (the demo's department). The robots' relative transforms
// are checked against the simulator's truth and the merged map against the world. Other cases
// kill the server (SIGKILL) mid-run and restart it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/merge_e2e/merge_e2e_fixture.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

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
TEST_F(DetectionMergeE2eTest, ServerKilledAndRestartedMidRunLosesNothing) {
  RunWithServerRestartAndCheck();
}

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

// Local SLAM on whole simulator scenarios, in process: no wrong loop closure at the building
// lap's end; its heading does not wander; another robot driving ahead does not hold the follower
// back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "robot_agent/bench/sim_slam_run.h"
#include "robot_agent/slam/scan_matching_slam.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

std::string Scenario(const std::string& name) {
  return testing::SourceDir() + "/robot_agent/sim/scenarios/" + name + ".yaml";
}

// The end pose relative to the start, against the truth's (the benchmarks' end-point error).
double EndPointError(const SimSlamRun& run) {
  const Rigid2d estimated = run.estimate.front().pose.inverse() * run.estimate.back().pose;
  const Rigid2d truth = run.ground_truth.front().pose.inverse() * run.ground_truth.back().pose;
  return (estimated.translation() - truth.translation()).norm();
}

// 427 m of corridors with long plain walls. At the lap's end, the scan of the corridor corner
// where the robot started also matches the room behind that corner's walls, 3.4 m away, with a
// perfect score; that closure left the lap 3.4 m off until loop closure learned to refuse
// matches that see the map's walls from behind. Without a closure the lap ends 0.1-0.4 m off:
// along the plain corridors the position is odometry's, and the least change anywhere in local
// SLAM moves it within that range, so the bound is the alias's, not the benchmark's figure.
TEST(SimulatedLapTest, ScanMatchingClosesTheBuildingLap) {
  ScanMatchingSlam slam;
  SimSlamRun run;
  std::string error;
  ASSERT_TRUE(RunSimulatedScenario(Scenario("building_1lap"), &slam, &run, &error)) << error;
  ASSERT_GT(run.estimate.size(), 5000u);
  EXPECT_LT(EndPointError(run), 1.0) << slam.Statistics();
}

// The largest heading error along the run, with both trajectories' starts laid on each other.
double WorstHeadingError(const SimSlamRun& run) {
  double worst = 0.0;
  for (size_t i = 0; i < run.estimate.size(); ++i) {
    const double estimated = (run.estimate.front().pose.inverse() * run.estimate[i].pose).rotation();
    const double truth = (run.ground_truth.front().pose.inverse() * run.ground_truth[i].pose).rotation();
    worst = std::max(worst, std::abs(NormalizeAngle(estimated - truth)));
  }
  return worst;
}

// The frontend matched one return per 5 cm voxel. A thinning that picks returns by their
// measured positions in beam order picks them by their range noise as well, and the matches
// turned: at true poses, -0.012 deg per scan with 10 cm voxels, +0.010 deg in reverse beam order,
// 0.000 deg without range noise or without thinning (match_bias). With 10 cm or 4.9 cm voxels this
// lap's heading wandered up to 1.8 or 2.5 deg and its end landed 2-4 m off; 5 cm voxels were
// spared by luck (0.20 deg). Near beams are thinned by index now (ThinBeams): 0.18 deg.
TEST(SimulatedLapTest, TheBuildingLapsHeadingDoesNotWander) {
  ScanMatchingSlam slam;
  SimSlamRun run;
  std::string error;
  ASSERT_TRUE(RunSimulatedScenario(Scenario("building_1lap"), &slam, &run, &error)) << error;
  ASSERT_EQ(run.estimate.size(), run.ground_truth.size());
  EXPECT_LT(WorstHeadingError(run), 0.6 * M_PI / 180.0) << slam.Statistics();
}

// The merge end-to-end test's short scenario: robot1 drives 35 s with robot3 3 m ahead going the
// same way. The other robot's back, mapped at every insertion, left a trail whose front end held
// robot1 back: its local SLAM ended 1.86-2.04 m short (4 seeds). Returns off small objects that did
// not stay put since the last scan stay out of the local map now: 0.005-0.21 m on those seeds.
// Seeds 23 and 25 still froze robot1 for 4 s (3.2 and 3.8 m short): in the plain corridor robot3's
// back was the only surface facing along it, so the corridor test took that direction as observed
// and the match followed robot3 (once a return off its flank persisted and was mapped, robot3
// showed at the same place scan after scan). Small objects that moved since the last scan (judged
// at the odometry prediction) are left out of the match now: 0.02-0.29 m over seeds 21-28.
TEST(SimulatedLapTest, ARobotDrivingAheadDoesNotHoldTheFollowerBack) {
  std::ifstream in(testing::SourceDir() + "/tests/merge_e2e/east_end_3robots.yaml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string scenario = text.str();
  const size_t seed_at = scenario.find("\nseed: 21\n");
  ASSERT_NE(seed_at, std::string::npos);
  const testing::ScopedTempDir temp("driving_ahead");
  const std::string& dir = temp.path();
  for (int seed = 21; seed <= 28; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::string path = dir + "/east_end_" + std::to_string(seed) + ".yaml";
    std::ofstream(path) << scenario.substr(0, seed_at) << "\nseed: " << seed << "\n"
                        << scenario.substr(seed_at + 10);
    ScanMatchingSlam slam;
    SimSlamRun run;
    std::string error;
    ASSERT_TRUE(RunSimulatedScenario(path, &slam, &run, &error)) << error;
    ASSERT_GT(run.estimate.size(), 300u);
    EXPECT_LT(EndPointError(run), 0.5) << slam.Statistics();
  }
}

}  // namespace
}  // namespace fleetmap

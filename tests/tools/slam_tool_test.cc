// Runs fleetmap-sim and fleetmap-slam as processes (found under FLEETMAP_BINARY_DIR): a
// simulated multi-robot scenario's log, mapped offline, checked against the simulator's truth.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "shared/io/trajectory_file.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// The end pose relative to the start, against the truth's (the benchmarks' end-point error).
double EndPointError(const Trajectory& estimate, const Trajectory& truth) {
  const Rigid2d estimated = estimate.front().pose.inverse() * estimate.back().pose;
  const Rigid2d expected = truth.front().pose.inverse() * truth.back().pose;
  return (estimated.translation() - expected.translation()).norm();
}

// The merge end-to-end test's scenario: robot1 drives 35 s with robot3 3 m ahead going the same
// way, and nothing masks robot3 in its scans. Mapped at every insertion, robot3's back held
// robot1's local SLAM back by 1.86-2.04 m (4 seeds); returns off small objects that did not stay
// put since the last scan now stay out of the local map.
TEST(SlamToolTest, MapsTheFollowerOfAnotherRobotFromItsSimulatedLog) {
  const testing::ScopedTempDir temp("fleetmap-slam-tool");
  const std::string& dir = temp.path();
  const std::string scenario = testing::SourceDir() + "/tests/merge_e2e/east_end_3robots.yaml";
  ASSERT_EQ(
      testing::RunProgram("robot_agent/sim/fleetmap-sim",
                          "--scenario " + scenario + " --out " + dir + "/sim --no-camera --quiet",
                          dir + "/sim.log"),
      0);
  ASSERT_EQ(testing::RunProgram("robot_agent/slam/fleetmap-slam",
                                "--log " + dir + "/sim/robot1.clf --out " + dir + "/slam --quiet",
                                dir + "/slam.log"),
            0);
  Trajectory estimate, truth;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(dir + "/slam/trajectory.txt", &estimate, &error)) << error;
  ASSERT_TRUE(ReadTrajectory(dir + "/sim/robot1.gt.txt", &truth, &error)) << error;
  ASSERT_GT(estimate.size(), 300u);
  ASSERT_FALSE(truth.empty());
  EXPECT_TRUE(std::filesystem::exists(dir + "/slam/map.pgm"));
  EXPECT_LT(EndPointError(estimate, truth), 0.5);
}

}  // namespace
}  // namespace fleetmap

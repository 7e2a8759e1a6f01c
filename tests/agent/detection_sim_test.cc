// Detection inside the agent, on a live simulated scenario: two robots in a corridor, one driving
// past the other, which stands and looks back. Each agent runs the whole path (simulator ->
// camera + laser -> RobotDetector -> outbox -> uploader -> real server), and every detection the
// server stores must agree with the simulator's ground truth.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <map>
#include <vector>

#include "robot_agent/agent/agent.h"
#include "robot_agent/agent/detection_factory.h"
#include "robot_agent/agent/sim_detection_setup.h"
#include "robot_agent/agent/sim_source.h"
#include "robot_agent/sim/simulation.h"
#include "tests/agent/sim_agents.h"
#include "tests/agent/test_server.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::SimAgentConfig;
using testing::SimGroundTruth;
using testing::WriteScenario;

TEST(AgentDetectionTest, SimulatorSetupLearnsEveryMarkerColour) {
  const testing::ScopedTempDir dir("agent_detect_setup");
  const std::string scenario = WriteScenario(dir.path());
  std::string error;
  auto source = SimSource::Open(scenario, "robot1", true, &error);
  ASSERT_NE(source, nullptr) << error;
  DetectionSetup setup;
  ASSERT_TRUE(MakeSimDetectionSetup(source->simulation(), {}, &setup, &error)) << error;
  ASSERT_EQ(setup.colours.markers.size(), 2u);
  EXPECT_EQ(setup.colours.markers[0].robot_id, "robot1");
  EXPECT_EQ(setup.colours.markers[1].robot_id, "robot2");
  EXPECT_GT(setup.colours.background.total(), 0.0);
  // The simulator's camera: 60 degrees over 640 columns, 0.1 m ahead of the robot centre.
  EXPECT_NEAR(setup.camera.fx, 554.256, 0.01);
  EXPECT_NEAR(setup.camera.cx, 319.5, 1e-9);
  EXPECT_NEAR(setup.camera.camera_in_robot.translation().x(), 0.1, 1e-9);
  EXPECT_NEAR(setup.geometry.marker_top, 0.65, 1e-9);
}

TEST(AgentDetectionTest, DetectionsOfTheOtherRobotReachTheServerAndMatchGroundTruth) {
  const testing::ScopedTempDir temp("agent_detect_sim");
  const std::string& dir = temp.path();
  const std::string scenario = WriteScenario(dir);
  const auto truth = SimGroundTruth(scenario);
  ASSERT_FALSE(truth.empty());
  auto server = testing::StartServer(0);
  ASSERT_NE(server, nullptr);

  const std::vector<std::string> robots = {"robot1", "robot2"};
  for (const std::string& robot : robots) {
    std::string error;
    auto agent = Agent::Create(SimAgentConfig(scenario, robot, dir, server->port()), &error);
    ASSERT_NE(agent, nullptr) << error;
    EXPECT_EQ(agent->Run(/*stay=*/false), kAgentOk);
    const std::string status = agent->StatusLine();
    EXPECT_THAT(status, ::testing::HasSubstr("detections queued="));
    // The returns off the robot it saw were kept out of its local SLAM.
    const size_t masked = status.find("masked returns=");
    ASSERT_NE(masked, std::string::npos) << status;
    EXPECT_GT(std::stol(status.substr(masked + 15)), 0) << status;
  }

  std::map<std::string, int> seen_by;
  double worst = 0.0;
  double sum_squares = 0.0;
  const auto records = server->store()->DetectionsAfter(0);
  for (const DetectionRecord& record : records) {
    const RobotDetection& d = record.detection;
    const int observer = d.observer_id == "robot1" ? 0 : 1;
    ASSERT_EQ(d.observed_id, robots[1 - observer]) << "a robot only sees the other one";
    const auto poses = truth.find(std::lround(d.timestamp * 1000.0));
    ASSERT_NE(poses, truth.end()) << "detection time " << d.timestamp << " is not a tick";
    const Eigen::Vector2d expected = poses->second[static_cast<size_t>(observer)].inverse() *
                                     poses->second[static_cast<size_t>(1 - observer)].translation();
    const double error = (d.position_in_observer - expected).norm();
    worst = std::max(worst, error);
    sum_squares += error * error;
    ++seen_by[d.observer_id];
    // The covariance is honest about errors of this size: within 4 sigma along any axis.
    const Eigen::Vector2d residual = d.position_in_observer - expected;
    EXPECT_LT(residual.dot(d.covariance.inverse() * residual), 16.0 + 1e-9)
        << "at " << d.timestamp << " error " << error;
  }
  // Each sees the other in ~30 frames (5 Hz, 6 s in view); allow for a few misses.
  EXPECT_GE(seen_by["robot1"], 20);
  EXPECT_GE(seen_by["robot2"], 20);
  ASSERT_FALSE(records.empty());
  const double rms = std::sqrt(sum_squares / records.size());
  EXPECT_LT(rms, 0.03);
  EXPECT_LT(worst, 0.06);
  std::printf("detections: robot1 %d, robot2 %d; error RMS %.4f m, max %.4f m\n", seen_by["robot1"],
              seen_by["robot2"], rms, worst);
}

}  // namespace
}  // namespace fleetmap

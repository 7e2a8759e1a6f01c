#include "tests/agent/sim_agents.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "robot_agent/sim/simulation.h"

namespace fleetmap::testing {

std::string WriteScenario(const std::string& dir) {
  const std::string path = dir + "/corridor_pass.yaml";
  std::ofstream(path) << R"(name: corridor_pass
world: rectangle
seed: 5
duration: 12
robots:
  - name: robot1
    start: {x: 1.2, y: 1.7, theta: 0}
    route: {waypoints: [[9.0, 1.7]], speed: 0.5}
  - name: robot2
    start: {x: 6.5, y: 0.6, theta: 3.14159265}
    start_delay: 100
    route: {waypoints: [[7.5, 0.6]], speed: 0.5}
)";
  return path;
}

std::map<long, std::vector<Rigid2d>> SimGroundTruth(const std::string& scenario) {
  std::string error;
  auto simulation = sim::Simulation::FromFile(scenario, &error, /*camera_enabled=*/false);
  EXPECT_NE(simulation, nullptr) << error;
  std::map<long, std::vector<Rigid2d>> truth;
  if (!simulation) return truth;
  while (!simulation->Done()) {
    truth[std::lround(simulation->time() * 1000.0)] = simulation->TruePoses();
    simulation->Step();
  }
  return truth;
}

AgentConfig SimAgentConfig(const std::string& scenario, const std::string& robot,
                           const std::string& dir, int port) {
  AgentConfig config;
  config.robot_id = robot;
  config.server_address = "127.0.0.1:" + std::to_string(port);
  config.outbox_path = dir + "/" + robot + ".db";
  config.source.type = SourceConfig::Type::kSimulator;
  config.source.scenario = scenario;
  config.source.sim_robot = robot;
  config.source.sim_camera = true;
  config.source.speed = 0.0;
  config.upload.uploader.backoff.initial = 0.02;
  config.upload.uploader.backoff.max = 0.2;
  config.upload.drain_timeout = 20.0;
  config.map.subscribe = false;
  config.map.reconnect.initial = 0.02;
  config.map.reconnect.max = 0.2;
  config.status_period = 0.0;
  config.detection.enabled = true;
  return config;
}

}  // namespace fleetmap::testing

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "robot_agent/sim/output_writer.h"
#include "robot_agent/sim/simulation.h"
#include "robot_agent/sim/world_io.h"
#include "tests/support/test_support.h"

namespace fleetmap::sim {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<Simulation> Department3(bool camera, std::string* error,
                                        const OdometryOptions* odometry = nullptr) {
  Scenario scenario;
  if (!LoadScenario(ShippedScenariosDir() + "/department_3robots.yaml", &scenario, error)) {
    return nullptr;
  }
  scenario.camera.enabled = camera;
  if (odometry) scenario.odometry = *odometry;
  World world;
  if (!LoadWorld(scenario.world_path, &world, error)) return nullptr;
  return Simulation::Create(scenario, std::move(world), error);
}

TEST(SimulationTest, ZeroNoiseOdometryEqualsGroundTruth) {
  OdometryOptions exact;
  exact.wheel_noise = 0.0;
  exact.left_wheel_error = 0.0;
  exact.right_wheel_error = 0.0;
  exact.baseline_error = 0.0;
  std::string error;
  std::unique_ptr<Simulation> sim = Department3(false, &error, &exact);
  ASSERT_NE(sim, nullptr) << error;
  sim->set_end_time(30.0);
  std::vector<Rigid2d> starts;
  for (const SimRobotInfo& robot : sim->robots()) starts.push_back(robot.route.start);
  double travelled = 0.0;
  int compared = 0;
  while (!sim->Done()) {
    for (const SensorPacket& packet : sim->Step().packets) {
      if (!packet.odometry) continue;
      const Rigid2d expected = starts[packet.robot_index].inverse() * packet.ground_truth;
      const Rigid2d& odometry = packet.odometry->robot_pose;
      ASSERT_NEAR((odometry.translation() - expected.translation()).norm(), 0.0, 1e-6);
      ASSERT_NEAR(NormalizeAngle(odometry.rotation() - expected.rotation()), 0.0, 1e-9);
      travelled = std::max(travelled, expected.translation().norm());
      ++compared;
    }
  }
  EXPECT_GE(compared, 1500);
  EXPECT_GT(travelled, 5.0);  // the robots really moved
}

TEST(SimulationTest, DefaultOdometryDriftsButStaysPlausible) {
  std::string error;
  std::unique_ptr<Simulation> sim = Department3(false, &error);
  ASSERT_NE(sim, nullptr) << error;
  sim->set_end_time(40.0);
  const Rigid2d start = sim->robots()[0].route.start;
  SensorPacket last;
  while (!sim->Done()) {
    for (SensorPacket& packet : sim->Step().packets) {
      if (packet.robot_index == 0 && packet.odometry) last = packet;
    }
  }
  const Rigid2d truth = start.inverse() * last.ground_truth;
  const double error_m = (last.odometry->robot_pose.translation() - truth.translation()).norm();
  EXPECT_GT(error_m, 1e-4);
  EXPECT_LT(error_m, 0.1 * truth.translation().norm() + 0.1);
}

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string RunToFolder(const std::string& dir) {
  std::string error;
  std::unique_ptr<Simulation> sim = Department3(true, &error);
  if (!sim) return error;
  sim->set_end_time(2.0);
  std::unique_ptr<OutputWriter> writer = OutputWriter::Open(dir, *sim, &error);
  if (!writer) return error;
  while (!sim->Done()) {
    if (!writer->Write(sim->Step(), &error)) return error;
  }
  return writer->Close(&error) ? "" : error;
}

TEST(SimulationTest, SameSeedGivesByteIdenticalFiles) {
  const testing::ScopedTempDir temp_a("sim_same_seed_a");
  const testing::ScopedTempDir temp_b("sim_same_seed_b");
  const std::string& a = temp_a.path();
  const std::string& b = temp_b.path();
  ASSERT_EQ(RunToFolder(a), "");
  ASSERT_EQ(RunToFolder(b), "");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(a)) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), a);
    EXPECT_EQ(ReadAll(entry.path()), ReadAll(fs::path(b) / relative)) << relative;
    ++files;
  }
  // manifest, visibility, 3 x (log, ground truth, index, >= 2 frames), 3 world files
  EXPECT_GE(files, 1 + 1 + 3 * 5 + 3);
  EXPECT_TRUE(fs::exists(fs::path(a) / "robot1_camera" / "frame_000000.png"));
}

}  // namespace
}  // namespace fleetmap::sim

#include "robot_agent/agent/sim_source.h"

#include <filesystem>
#include <utility>

namespace fleetmap {
namespace {

CameraImage ToCameraImage(const sim::CameraFrame& frame) {
  CameraImage image;
  image.timestamp = frame.timestamp;
  image.width = frame.image.width;
  image.height = frame.image.height;
  image.bgr = frame.image.pixels;
  // The simulator renders R G B; the detector reads B G R.
  for (size_t i = 0; i + 2 < image.bgr.size(); i += 3) std::swap(image.bgr[i], image.bgr[i + 2]);
  return image;
}

}  // namespace

std::unique_ptr<SimSource> SimSource::Open(const std::string& scenario, const std::string& robot,
                                           bool camera, std::string* error) {
  std::string path = scenario;
  if (!std::filesystem::exists(path)) {
    const std::string shipped = sim::ShippedScenariosDir() + "/" + scenario + ".yaml";
    if (!std::filesystem::exists(shipped)) {
      *error = "source.simulator.scenario: '" + scenario +
               "' is neither a file nor a shipped "
               "scenario (" +
               sim::ShippedScenariosDir() + ")";
      return nullptr;
    }
    path = shipped;
  }
  std::string why;
  std::unique_ptr<sim::Simulation> simulation = sim::Simulation::FromFile(path, &why, camera);
  if (!simulation) {
    *error = "source.simulator.scenario: " + why;
    return nullptr;
  }
  const auto& robots = simulation->robots();
  for (size_t i = 0; i < robots.size(); ++i) {
    if (robots[i].name == robot) {
      return std::unique_ptr<SimSource>(new SimSource(std::move(simulation), static_cast<int>(i)));
    }
  }
  std::string names;
  for (const auto& info : robots) names += (names.empty() ? "" : ", ") + info.name;
  *error =
      "source.simulator.robot: no robot '" + robot + "' in " + path + " (robots: " + names + ")";
  return nullptr;
}

bool SimSource::Next(SensorEvent* event) {
  while (ready_.empty()) {
    if (simulation_->Done()) return false;
    sim::StepResult step = simulation_->Step();
    for (sim::SensorPacket& packet : step.packets) {
      if (packet.robot_index != robot_index_) continue;
      if (!packet.odometry && !packet.laser && !packet.camera) continue;
      SensorEvent out;
      out.timestamp = packet.timestamp;
      out.ground_truth = packet.ground_truth;
      out.odometry = std::move(packet.odometry);
      out.laser = std::move(packet.laser);
      if (packet.camera) out.camera = ToCameraImage(*packet.camera);
      ready_.push_back(std::move(out));
    }
  }
  *event = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

std::string SimSource::Describe() const {
  return "simulator " + simulation_->scenario().name + ", robot " +
         simulation_->robots()[static_cast<size_t>(robot_index_)].name;
}

}  // namespace fleetmap

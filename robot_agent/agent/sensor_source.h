#ifndef FLEETMAP_ROBOT_AGENT_AGENT_SENSOR_SOURCE_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_SENSOR_SOURCE_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot_agent/agent/agent_config.h"
#include "shared/io/carmen_log.h"

namespace fleetmap {

// One camera image: either a file to load (a log's camera index) or pixels (the simulator).
struct CameraImage {
  double timestamp = 0.0;
  std::string path;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> bgr;  // width * height * 3 bytes, B G R, rows packed
};

// What the robot's sensors produced at one instant; any part may be absent.
struct SensorEvent {
  double timestamp = 0.0;  // robot clock, seconds
  std::optional<OdometryRecord> odometry;
  std::optional<LaserRecord> laser;
  std::optional<CameraImage> camera;
  std::optional<Rigid2d> ground_truth;  // simulator only
};

// Where the agent's sensor data comes from: a recorded log or a live (simulated) robot. Events
// come in time order.
class SensorSource {
 public:
  virtual ~SensorSource() = default;
  // The next event; false at the end of the data or on an error (then error() says why).
  virtual bool Next(SensorEvent* event) = 0;
  virtual const std::string& error() const = 0;
  // E.g. "CARMEN log intel.clf" or "simulator department, robot r1".
  virtual std::string Describe() const = 0;
};

// The source the configuration asks for; nullptr + `error` (naming the field) when it cannot
// be opened.
std::unique_ptr<SensorSource> OpenSensorSource(const SourceConfig& config, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_SENSOR_SOURCE_H_

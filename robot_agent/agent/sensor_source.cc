#include "robot_agent/agent/sensor_source.h"

#include "robot_agent/agent/carmen_log_source.h"
#ifdef FLEETMAP_AGENT_HAVE_SIM
#include "robot_agent/agent/sim_source.h"
#endif

namespace fleetmap {

std::unique_ptr<SensorSource> OpenSensorSource(const SourceConfig& config, std::string* error) {
  if (config.type == SourceConfig::Type::kCarmen) {
    std::string why;
    std::unique_ptr<SensorSource> source =
        CarmenLogSource::Open(config.log_path, config.camera_index, &why);
    if (!source) *error = "source.carmen: " + why;
    return source;
  }
#ifdef FLEETMAP_AGENT_HAVE_SIM
  return SimSource::Open(config.scenario, config.sim_robot, config.sim_camera, error);
#else
  *error = "source.simulator: this build has no simulator library (robot_agent/sim)";
  return nullptr;
#endif
}

}  // namespace fleetmap

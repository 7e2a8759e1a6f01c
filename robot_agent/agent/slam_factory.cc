#include "robot_agent/agent/slam_factory.h"

#include "robot_agent/slam/backend_factory.h"
#include "robot_agent/slam/scan_matching_slam.h"

namespace fleetmap {

std::vector<std::string> AvailableSlamAlgorithms() { return LocalSlamAlgorithms(); }

std::unique_ptr<LocalSlam> CreateLocalSlam(const SlamConfig& config, const std::string& robot_id,
                                           std::string* error) {
  if (config.algorithm == "scan-matching") {
    ScanMatchingSlamOptions options;
    options.robot_id = robot_id;
    options.max_range = static_cast<float>(config.max_range);
    options.insert_min_translation = config.min_translation;
    options.insert_min_rotation = config.min_rotation;
    options.submaps.max_scans = config.submap_scans;
    options.submaps.max_travel = config.submap_travel;
    options.submaps.grid.resolution = config.resolution;
    return std::make_unique<ScanMatchingSlam>(options);
  }
  // Other backends come with their own defaults.
  BackendChoice choice;
  choice.algorithm = config.algorithm;
  choice.robot_id = robot_id;
  std::string why;
  std::unique_ptr<LocalSlam> slam = MakeLocalSlam(choice, &why);
  if (!slam) *error = "slam.algorithm: " + why;
  return slam;
}

}  // namespace fleetmap

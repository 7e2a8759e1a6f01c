#include "robot_agent/agent/localizer_factory.h"

#include <algorithm>

#include "shared/io/map_file.h"

namespace fleetmap {

std::unique_ptr<MclLocalizer> CreateLocalizer(const LocalizationConfig& config,
                                              const OccupancyGrid& map) {
  MclLocalizerOptions options;
  options.mcl.kld.max_particles = config.particles;
  options.mcl.kld.min_particles = std::min(options.mcl.kld.min_particles, config.particles);
  options.mcl.seed = static_cast<uint32_t>(config.seed);
  options.laser.max_beams = config.beams;
  options.initial_pose = config.initial_pose;
  options.initial_position_std = config.initial_position_std;
  options.initial_heading_std = config.initial_heading_std;
  options.seeding.enabled = config.scan_seeding;
  options.mcl.recovery.enabled = config.random_injection;
  return std::make_unique<MclLocalizer>(map, options);
}

bool ReadLocalizationMap(const LocalizationConfig& config, OccupancyGrid* map, std::string* error) {
  std::string why;
  if (!ReadMap(config.map, map, &why)) {
    *error = "localization.map: " + why;
    return false;
  }
  return true;
}

}  // namespace fleetmap

#ifndef FLEETMAP_ROBOT_AGENT_AGENT_LOCALIZER_FACTORY_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_LOCALIZER_FACTORY_H_

#include <memory>
#include <string>

#include "robot_agent/agent/agent_config.h"
#include "robot_agent/localization/mcl_localizer.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// The agent's localization mode (agent_config.h, LocalizationConfig): the filter, from the
// configuration and the known map.
std::unique_ptr<MclLocalizer> CreateLocalizer(const LocalizationConfig& config,
                                              const OccupancyGrid& map);

// The known map from the configured file; false with a message naming the field otherwise.
bool ReadLocalizationMap(const LocalizationConfig& config, OccupancyGrid* map, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_LOCALIZER_FACTORY_H_

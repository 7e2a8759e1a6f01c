#ifndef FLEETMAP_ROBOT_AGENT_SIM_WORLD_IO_H_
#define FLEETMAP_ROBOT_AGENT_SIM_WORLD_IO_H_

#include <string>

#include "robot_agent/sim/world.h"

namespace fleetmap::sim {

// Loads a world from either
//  - a world file (`<name>.world.yaml`: `map:` naming a ROS map_server YAML beside it, plus
//    `name`, `wall_height`, `places` and coloured `patches`), or
//  - any plain ROS map_server YAML (`image:` key), giving a world without metadata.
// Fills `error` with a message naming the file on any problem.
bool LoadWorld(const std::string& path, World* world, std::string* error);

// Writes `<dir>/<world.name>.pgm`, `.yaml` (map_server: 0 occupied, 254 free, 205 unknown) and
// `.world.yaml`. Output is byte-identical for identical worlds.
bool SaveWorld(const std::string& dir, const World& world, std::string* error);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_WORLD_IO_H_

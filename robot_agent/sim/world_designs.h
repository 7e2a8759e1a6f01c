#ifndef FLEETMAP_ROBOT_AGENT_SIM_WORLD_DESIGNS_H_
#define FLEETMAP_ROBOT_AGENT_SIM_WORLD_DESIGNS_H_

#include <string>
#include <vector>

#include "robot_agent/sim/world.h"

namespace fleetmap::sim {

// The paper's manufactured map: a rectangular corridor ring whose outer walls measure exactly
// 21.3 m x 17 m (outer faces), corridors 2 m wide, plain walls. 0.05 m cells.
World MakeRectangleWorld();

// Two long parallel corridors (52 m) joined at their ends, rooms off both, two of them labs
// ("Lab_1" south-west, "Lab_2" north-east), coloured posters and a cabinet as distractors.
// 0.05 m cells.
World MakeDepartmentWorld();

// One floor whose corridor ring is over 400 m long (plus a cross corridor), rooms with doors,
// and long stretches of plain wall. 0.1 m cells.
World MakeBuildingWorld();

// The names MakeWorldByName accepts.
std::vector<std::string> DesignedWorldNames();
// Returns false for an unknown name.
bool MakeWorldByName(const std::string& name, World* world);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_WORLD_DESIGNS_H_

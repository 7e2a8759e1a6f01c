#ifndef FLEETMAP_ROBOT_AGENT_SIM_MAP_ACCURACY_H_
#define FLEETMAP_ROBOT_AGENT_SIM_MAP_ACCURACY_H_

#include "robot_agent/sim/world.h"
#include "shared/eval/wall_score.h"

namespace fleetmap::sim {

// The world's walls (its occupied cells) to score maps against (ScoreOnWalls): the same rule
// `fleetmapctl evaluate` applies to the world's exported PGM.
WallMask WorldWalls(const World& world, int reach = 1);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_MAP_ACCURACY_H_

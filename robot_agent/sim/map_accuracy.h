#ifndef FLEETMAP_ROBOT_AGENT_SIM_MAP_ACCURACY_H_
#define FLEETMAP_ROBOT_AGENT_SIM_MAP_ACCURACY_H_

#include <cstdint>

#include "robot_agent/sim/world.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::sim {

// How many of a map's occupied cells lie on the world's walls.
struct MapAccuracy {
  int64_t occupied = 0;
  int64_t near_wall = 0;  // of those, within one world cell of a blocked cell
  double fraction() const { return occupied > 0 ? static_cast<double>(near_wall) / occupied : 0.0; }
};

// Scores `grid` (cells with positive log-odds are occupied), placed in the world at
// `grid_in_world`: a cell counts when the world is blocked at its centre or one world cell
// around it (the wall crosses the cell or a neighbour).
MapAccuracy ScoreAgainstWalls(const OccupancyGrid& grid, const Rigid2d& grid_in_world,
                              const World& world);

// The same score at the best placement near `initial` (FitMapToWalls); `best` receives the
// placement when given.
MapAccuracy ScoreAgainstWallsBestFit(const OccupancyGrid& grid, const Rigid2d& initial,
                                     const World& world, Rigid2d* best = nullptr);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_MAP_ACCURACY_H_

#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SUBMAP_ASSEMBLY_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SUBMAP_ASSEMBLY_H_

#include <vector>

#include "shared/core/occupancy_grid.h"
#include "shared/core/submap.h"

namespace fleetmap {

// One grid in the local map frame from submaps placed at their `submap_in_local`: each target
// cell sums the log-odds of the submap cell under its centre (clamped to the grid limits).
// Rotated submaps are resampled by nearest neighbour, so no holes appear.
OccupancyGrid AssembleSubmaps(const std::vector<const Submap*>& submaps,
                              const OccupancyGridOptions& options);
// Adds one submap to `grid`: AssembleSubmaps is this over every submap, in order. For callers
// that hold their submaps packed and unpack one at a time.
void AddSubmapToAssembly(const Submap& submap, OccupancyGrid* grid);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SUBMAP_ASSEMBLY_H_

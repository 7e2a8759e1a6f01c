#ifndef FLEETMAP_MAP_SERVER_SERVER_GLOBAL_MAP_RENDERER_H_
#define FLEETMAP_MAP_SERVER_SERVER_GLOBAL_MAP_RENDERER_H_

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// Adds `weight` times the log-odds of `submap_grid` (in the submap frame) into `canvas` (global
// frame) with the submap placed at `submap_in_global`. Each canvas cell takes the submap cell
// under its centre (nearest neighbour), so rotated submaps leave no holes. Canvas values are
// plain sums (no clamping), so adding with weight +1 and later -1 removes a contribution
// exactly: the basis of incremental re-rendering when a submap gets a new revision or pose.
// Pure: no I/O, no threads.
void FuseSubmap(const OccupancyGrid& submap_grid, const Rigid2d& submap_in_global, float weight,
                OccupancyGrid* canvas);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_GLOBAL_MAP_RENDERER_H_

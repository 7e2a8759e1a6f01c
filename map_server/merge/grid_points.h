#ifndef FLEETMAP_MAP_SERVER_MERGE_GRID_POINTS_H_
#define FLEETMAP_MAP_SERVER_MERGE_GRID_POINTS_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// Centres of the wall cells (log-odds above `occupied_log_odds`) of `grid`, mapped through
// `grid_to_frame` into another frame.
std::vector<Eigen::Vector2d> OccupiedPoints(const OccupancyGrid& grid, float occupied_log_odds,
                                            const Rigid2d& grid_to_frame = Rigid2d());

// Keeps one point per `cell_size` square (the first one seen), then at most `max_points`
// evenly spread over the remainder: bounded work per match whatever the submap size.
std::vector<Eigen::Vector2d> VoxelFilter(const std::vector<Eigen::Vector2d>& points,
                                         double cell_size, size_t max_points);

// The mean of the points (zero for none).
Eigen::Vector2d Centroid(const std::vector<Eigen::Vector2d>& points);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_GRID_POINTS_H_

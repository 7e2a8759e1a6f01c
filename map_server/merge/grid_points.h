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

// The side a wall cell of `grid` was seen from: the unit vector (grid frame) towards the
// seen-free cells (log-odds below `free_log_odds`) within two cells of it; zero where the free
// cells lie on both sides (a thin wall seen from both) or there are none. Two maps of one wall
// of some thickness seen from opposite sides hold its two faces; only faces seen from the same
// side are the same surface.
Eigen::Vector2d WallNormalAt(const OccupancyGrid& grid, const CellIndex& cell, float free_log_odds);

// WallNormalAt() of every OccupiedPoints() point (same order), turned into `grid_to_frame`.
std::vector<Eigen::Vector2d> WallNormals(const OccupancyGrid& grid, float occupied_log_odds,
                                         float free_log_odds,
                                         const Rigid2d& grid_to_frame = Rigid2d());

// Indices of the points kept when thinning: one point per `cell_size` square (the first one
// seen), then at most `max_points` evenly spread over the remainder: bounded work per match
// whatever the submap size.
std::vector<size_t> VoxelFilterIndices(const std::vector<Eigen::Vector2d>& points,
                                       double cell_size, size_t max_points);

// The mean of the points (zero for none).
Eigen::Vector2d Centroid(const std::vector<Eigen::Vector2d>& points);
// The largest distance of the points from the origin (zero for none).
double Radius(const std::vector<Eigen::Vector2d>& points);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_GRID_POINTS_H_

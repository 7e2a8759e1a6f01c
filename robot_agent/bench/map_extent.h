#ifndef FLEETMAP_ROBOT_AGENT_BENCH_MAP_EXTENT_H_
#define FLEETMAP_ROBOT_AGENT_BENCH_MAP_EXTENT_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct MapExtentOptions {
  float occupied_probability = 0.65f;
  // The outermost wall along an axis: occupied cells within `band` (metres) of the robust
  // extreme (the `quantile` of their coordinates), whose median coordinate is the wall's position.
  double band = 0.3;
  double quantile = 0.002;
};

struct MapExtent {
  Eigen::Vector2d min = Eigen::Vector2d::Zero();  // west and south walls, world frame
  Eigen::Vector2d max = Eigen::Vector2d::Zero();  // east and north walls
  Eigen::Vector2d size() const { return max - min; }
};

// Measures the outer walls of a map along the world axes (table I of the paper: the length and
// height of the corridor ring). `world_from_map` brings map cells into the world frame (e.g. the
// alignment of the SLAM trajectory to ground truth). Empty when the map has no occupied cells.
std::optional<MapExtent> MeasureOuterWalls(const OccupancyGrid& map, const Rigid2d& world_from_map,
                                           const MapExtentOptions& options = MapExtentOptions());

// The same over points in the world frame, e.g. every return at its scan's estimated pose: the
// walls where the map draws them, without the cells' quantisation. On a 5 cm grid the cells
// alone read a perfect map of the rectangle up to a cell larger (0.3 % of its height), too
// coarse against a 0.5 % target. Empty without points.
std::optional<MapExtent> MeasureOuterWalls(const std::vector<Eigen::Vector2d>& points,
                                           const MapExtentOptions& options = MapExtentOptions());

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_BENCH_MAP_EXTENT_H_

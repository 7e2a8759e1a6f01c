#ifndef FLEETMAP_SHARED_MATCHING_POINT_FILTER_H_
#define FLEETMAP_SHARED_MATCHING_POINT_FILTER_H_

#include <vector>

#include <Eigen/Core>

namespace fleetmap {

// Keeps the first point of every `cell_size` x `cell_size` cell (in scan order), so that the
// dense returns near the robot do not outvote the sparse far ones and matching gets cheaper.
std::vector<Eigen::Vector2f> VoxelFilter(const std::vector<Eigen::Vector2f>& points,
                                         float cell_size);

// Drops points farther than `max_range` from the origin of their frame.
std::vector<Eigen::Vector2f> RangeFilter(const std::vector<Eigen::Vector2f>& points,
                                         float max_range);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_POINT_FILTER_H_

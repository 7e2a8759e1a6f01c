#ifndef FLEETMAP_SHARED_MATCHING_POINT_FILTER_H_
#define FLEETMAP_SHARED_MATCHING_POINT_FILTER_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/laser_scan.h"

namespace fleetmap {

// Keeps the first point of every `cell_size` x `cell_size` cell (in scan order), so that the
// dense returns near the robot do not outvote the sparse far ones and matching gets cheaper.
std::vector<Eigen::Vector2f> VoxelFilter(const std::vector<Eigen::Vector2f>& points,
                                         float cell_size);

// Keeps, of the beams whose returns are closer together than `min_spacing` (range times the
// angle between beams), every k-th beam by index, with k = min_spacing / that spacing rounded
// down; the others become kNoReturn. Like VoxelFilter, it stops the dense near returns from
// outvoting the sparse far ones. Unlike it, which returns survive does not depend on where the
// range noise put them: VoxelFilter keeps the first return in beam order to enter each voxel,
// more often one that noise pushed the way the beams sweep, and a match of the survivors is
// turned (-0.012 deg per scan with 10 cm voxels at true poses on the simulated building lap,
// +0.010 deg in reverse beam order, none without range noise; docs/BENCHMARKS.md, issue 8,
// session 14).
LaserScan ThinBeams(const LaserScan& scan, float min_spacing);

// Drops points farther than `max_range` from the origin of their frame.
std::vector<Eigen::Vector2f> RangeFilter(const std::vector<Eigen::Vector2f>& points,
                                         float max_range);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_POINT_FILTER_H_

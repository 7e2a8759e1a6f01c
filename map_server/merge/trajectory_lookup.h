#ifndef FLEETMAP_MAP_SERVER_MERGE_TRAJECTORY_LOOKUP_H_
#define FLEETMAP_MAP_SERVER_MERGE_TRAJECTORY_LOOKUP_H_

#include <optional>

#include "shared/core/trajectory.h"

namespace fleetmap {

// The pose at `time`, interpolated between the two poses around it when they are at most
// `max_gap` seconds apart; a time within `tolerance` of either end takes that end's pose.
// Nothing when the trajectory does not cover the time (no extrapolation: a guess here would
// become a wrong merge).
std::optional<Rigid2d> PoseAt(const Trajectory& trajectory, double time, double max_gap = 2.0,
                              double tolerance = 0.05);

// True when the poses are in non-decreasing time order with finite values.
bool IsValidTrajectory(const Trajectory& trajectory);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_TRAJECTORY_LOOKUP_H_

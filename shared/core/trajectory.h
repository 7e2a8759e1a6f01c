#ifndef FLEETMAP_SHARED_CORE_TRAJECTORY_H_
#define FLEETMAP_SHARED_CORE_TRAJECTORY_H_

#include <vector>

#include "shared/core/rigid2d.h"

namespace fleetmap {

struct StampedPose {
  double timestamp = 0.0;  // seconds
  Rigid2d pose;
};

// Poses in increasing time order.
using Trajectory = std::vector<StampedPose>;

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_TRAJECTORY_H_

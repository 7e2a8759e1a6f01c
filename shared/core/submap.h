#ifndef FLEETMAP_SHARED_CORE_SUBMAP_H_
#define FLEETMAP_SHARED_CORE_SUBMAP_H_

#include <cstdint>
#include <string>

#include "shared/core/occupancy_grid.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

// A piece of one robot's map, built from consecutive scans: what local SLAM produces, what the
// agent uploads and what the merge engine places. The grid lives in the submap's own frame, so
// moving `submap_in_local` moves the whole submap rigidly.
struct Submap {
  std::string robot_id;
  int64_t submap_id = 0;  // consecutive per robot, from 0
  int64_t revision = 0;   // grows every time local SLAM re-publishes this submap
  // The submap frame in the robot's local map frame (the anchor pose).
  Rigid2d submap_in_local;
  // The poses of the scans inserted into it, robot in the local map frame.
  Trajectory scan_poses;
  // Occupancy in the submap frame.
  OccupancyGrid grid;
  // No more scans will be inserted.
  bool finished = false;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_SUBMAP_H_

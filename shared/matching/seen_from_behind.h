#ifndef FLEETMAP_SHARED_MATCHING_SEEN_FROM_BEHIND_H_
#define FLEETMAP_SHARED_MATCHING_SEEN_FROM_BEHIND_H_

#include <Eigen/Core>
#include <vector>

#include "shared/core/rigid2d.h"
#include "shared/matching/match_grid.h"

namespace fleetmap {

// A scan matched to a map must see the map's walls from the side the map's own scans saw them.
// A distance grid keeps no side: a wall seen from a corridor and the same wall seen from the
// room behind it are one line, so a scan of a corridor corner matches a room's corner on the
// far side of the corridor's walls perfectly (the end of the simulated building's lap: 0.99,
// 3.4 m off). What tells them apart is the space in front of each wall: the map's rays crossed
// it on the side they came from, and never the other.
struct SeenFromBehindOptions {
  // Returns this close to a wall of the map (metres) are judged...
  double on_wall_distance = 0.1;
  // ... by the cell this far before them along the beam: the map saw it when it saw the wall
  // from the beam's side. More than the walls' thickness, less than a corridor's width.
  double look_back = 0.2;
};

struct SeenFromBehind {
  int on_walls = 0;  // returns on walls of the map, in cells it saw
  int behind = 0;    // ... of them, those whose beam comes from space the map never saw
  double fraction() const { return on_walls > 0 ? static_cast<double>(behind) / on_walls : 0.0; }
};

// Judges `points_in_robot` (returns, robot frame; beams from `sensor_in_robot`) with the robot at
// `robot_in_grid`, against a grid that tracks observed cells (MatchGridOptions::track_observed;
// with an untracked grid nothing is behind).
SeenFromBehind WallsSeenFromBehind(const std::vector<Eigen::Vector2f>& points_in_robot,
                                   const Eigen::Vector2d& sensor_in_robot, const MatchGrid& grid,
                                   const Rigid2d& robot_in_grid,
                                   const SeenFromBehindOptions& options = SeenFromBehindOptions());

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_SEEN_FROM_BEHIND_H_

#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SEEN_SURFACE_FILTER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SEEN_SURFACE_FILTER_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"
#include "shared/matching/match_grid.h"

namespace fleetmap {

// The points of a scan (robot frame) that can be matched against `target` at `pose`: those on
// surfaces the target has seen. A point is left out when, at `pose`, it lands in a cell no scan
// of the target observed and farther than `max_unseen_distance` from every surface in it. That
// is a surface the map has not seen yet: the far face of a box that comes into view as the robot
// turns round it, pulled onto the face next to it, turned the match by ~1 degree (tests/slam: ScanMatchingSlamTest.TurningPastBoxesKeepsTheHeading). Points
// just behind a mapped wall (the cells behind a wall are never observed) stay, so the filter
// does not push the scan off its walls. When fewer than `min_kept_share` of the points would
// stay (entering new space, a poor pose), all are returned. Needs a target that tracks
// observed cells (MatchGridOptions::track_observed); otherwise every point stays.
std::vector<Eigen::Vector2f> PointsOnSeenSurfaces(const std::vector<Eigen::Vector2f>& points,
                                                  const MatchGrid& target, const Rigid2d& pose,
                                                  double max_unseen_distance,
                                                  double min_kept_share = 1.0 / 3.0);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SEEN_SURFACE_FILTER_H_

#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SMALL_FOREGROUND_OBJECTS_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SMALL_FOREGROUND_OBJECTS_H_

#include <vector>

#include <Eigen/Core>

namespace fleetmap {

struct SmallForegroundObjectOptions {
  // Largest object (metres, first to last return) counted as small: a robot or a person seen
  // from any side, not a stretch of wall.
  double max_size = 0.8;
  // Consecutive returns whose ranges differ by more than this (metres) lie on different objects.
  double depth_jump = 0.3;
  // Consecutive returns farther apart in bearing than this (radians) have beams between them
  // that saw nothing: open space, as far as the object is concerned.
  double max_bearing_step = 0.06;
};

// Which returns (robot frame, in beam order) lie on small objects standing in front of what is
// around them: the returns are split where the range jumps, and a run no longer than max_size
// whose neighbours on both sides are farther away (or missing) is such an object. Another robot,
// a person, a pillar or a box; never a wall, whose runs continue into neighbours at the same
// depth or lead towards or away from the sensor.
std::vector<bool> SmallForegroundObjects(const std::vector<Eigen::Vector2f>& points_in_beam_order,
                                         const SmallForegroundObjectOptions& options);

// The same, saying which object each return lies on: 0, 1, 2, ... in beam order, -1 for returns
// on no small object.
std::vector<int> SmallForegroundObjectIds(const std::vector<Eigen::Vector2f>& points_in_beam_order,
                                          const SmallForegroundObjectOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SMALL_FOREGROUND_OBJECTS_H_

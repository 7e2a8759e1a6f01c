#ifndef FLEETMAP_ROBOT_AGENT_SLAM_ODOMETRY_BUFFER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_ODOMETRY_BUFFER_H_

#include <deque>
#include <optional>
#include <string>

#include "shared/core/trajectory.h"

namespace fleetmap {

// Recent odometry readings, interpolated at scan times. Shared by every local SLAM backend.
class OdometryBuffer {
 public:
  // Fails on a reading older than the previous one or with non-finite values.
  bool Add(const StampedPose& odometry, std::string* error);
  bool empty() const { return readings_.empty(); }
  // Odometry at `time`: interpolated between the readings around it, or the nearest reading
  // when `time` lies outside them. Empty when there has been no reading. Forgets readings that
  // are no longer needed for times at or after `time`.
  std::optional<Rigid2d> PoseAt(double time);

 private:
  std::deque<StampedPose> readings_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_ODOMETRY_BUFFER_H_

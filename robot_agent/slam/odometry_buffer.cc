#include "robot_agent/slam/odometry_buffer.h"

#include <cmath>
#include <sstream>

namespace fleetmap {

bool OdometryBuffer::Add(const StampedPose& odometry, std::string* error) {
  if (!std::isfinite(odometry.timestamp) || !odometry.pose.IsFinite()) {
    if (error) *error = "odometry reading with a non-finite time or pose";
    return false;
  }
  if (!readings_.empty() && odometry.timestamp < readings_.back().timestamp) {
    std::ostringstream message;
    message.precision(17);
    message << "odometry time goes backwards: " << odometry.timestamp << " after "
            << readings_.back().timestamp;
    if (error) *error = message.str();
    return false;
  }
  readings_.push_back(odometry);
  return true;
}

std::optional<Rigid2d> OdometryBuffer::PoseAt(double time) {
  if (readings_.empty()) return std::nullopt;
  // Drop readings entirely before `time`, keeping the last one at or before it.
  while (readings_.size() >= 2 && readings_[1].timestamp <= time) readings_.pop_front();
  const StampedPose& first = readings_.front();
  if (time <= first.timestamp || readings_.size() == 1) return first.pose;
  const StampedPose& second = readings_[1];
  const double span = second.timestamp - first.timestamp;
  if (span <= 0.0) return second.pose;
  return Interpolate(first.pose, second.pose, (time - first.timestamp) / span);
}

}  // namespace fleetmap

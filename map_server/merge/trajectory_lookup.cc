#include "map_server/merge/trajectory_lookup.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

std::optional<Rigid2d> PoseAt(const Trajectory& trajectory, double time, double max_gap,
                              double tolerance) {
  if (trajectory.empty() || !std::isfinite(time)) return std::nullopt;
  if (time <= trajectory.front().timestamp) {
    if (trajectory.front().timestamp - time <= tolerance) return trajectory.front().pose;
    return std::nullopt;
  }
  if (time >= trajectory.back().timestamp) {
    if (time - trajectory.back().timestamp <= tolerance) return trajectory.back().pose;
    return std::nullopt;
  }
  const auto after = std::lower_bound(
      trajectory.begin(), trajectory.end(), time,
      [](const StampedPose& p, double t) { return p.timestamp < t; });
  const auto before = std::prev(after);
  const double gap = after->timestamp - before->timestamp;
  if (gap > max_gap) {
    if (time - before->timestamp <= tolerance) return before->pose;
    if (after->timestamp - time <= tolerance) return after->pose;
    return std::nullopt;
  }
  const double t = gap > 0.0 ? (time - before->timestamp) / gap : 0.0;
  return Interpolate(before->pose, after->pose, t);
}

bool IsValidTrajectory(const Trajectory& trajectory) {
  for (size_t i = 0; i < trajectory.size(); ++i) {
    if (!std::isfinite(trajectory[i].timestamp) || !trajectory[i].pose.IsFinite()) return false;
    if (i > 0 && trajectory[i].timestamp < trajectory[i - 1].timestamp) return false;
  }
  return true;
}

}  // namespace fleetmap

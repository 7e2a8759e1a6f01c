#include "map_server/ctl/localization_error.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

LocalizationError ScoreTrajectory(const Trajectory& estimated, const Trajectory& truth,
                                  double tolerance) {
  LocalizationError error;
  for (const StampedPose& pose : estimated) {
    // The true pose nearest in time.
    const auto after =
        std::lower_bound(truth.begin(), truth.end(), pose.timestamp,
                         [](const StampedPose& p, double t) { return p.timestamp < t; });
    const StampedPose* nearest = nullptr;
    if (after != truth.end()) nearest = &*after;
    if (after != truth.begin() && (!nearest || pose.timestamp - (after - 1)->timestamp <
                                                   nearest->timestamp - pose.timestamp)) {
      nearest = &*(after - 1);
    }
    if (!nearest || std::abs(nearest->timestamp - pose.timestamp) > tolerance) continue;
    const double position = (pose.pose.translation() - nearest->pose.translation()).norm();
    const double heading =
        std::abs(NormalizeAngle(pose.pose.rotation() - nearest->pose.rotation()));
    ++error.matched;
    error.mean_position += position;
    error.mean_heading += heading;
    error.max_position = std::max(error.max_position, position);
    error.max_heading = std::max(error.max_heading, heading);
    error.final_position = position;
    error.final_heading = heading;
  }
  if (error.matched > 0) {
    error.mean_position /= error.matched;
    error.mean_heading /= error.matched;
  }
  return error;
}

}  // namespace fleetmap

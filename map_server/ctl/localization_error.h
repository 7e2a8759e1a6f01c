#ifndef FLEETMAP_MAP_SERVER_CTL_LOCALIZATION_ERROR_H_
#define FLEETMAP_MAP_SERVER_CTL_LOCALIZATION_ERROR_H_

#include "shared/core/trajectory.h"

namespace fleetmap {

// How far a localizing robot's poses are from the truth.
struct LocalizationError {
  int matched = 0;             // estimated poses with a true pose at the same time
  double mean_position = 0.0;  // metres
  double max_position = 0.0;
  double mean_heading = 0.0;  // radians
  double max_heading = 0.0;
  double final_position = 0.0;  // at the last matched pose
  double final_heading = 0.0;
};

// Pure scoring, both trajectories in the same frame. An estimated pose counts when the truth
// (sorted by time) has a pose within `tolerance` seconds of it.
LocalizationError ScoreTrajectory(const Trajectory& estimated, const Trajectory& truth,
                                  double tolerance = 0.005);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_CTL_LOCALIZATION_ERROR_H_

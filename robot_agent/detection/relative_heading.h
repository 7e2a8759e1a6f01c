#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_RELATIVE_HEADING_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_RELATIVE_HEADING_H_

#include <optional>

#include "robot_agent/detection/detection.h"

namespace fleetmap {

struct RelativeHeading {
  double heading = 0.0;   // rotation of the observed robot's frame in the observer's frame
  double variance = 0.0;  // rad^2, first-order propagation of both detections' covariances
};

// When robot A sees B and B sees A at (nearly) the same time, the two bearings fix B's heading in
// A's frame: A's position seen from B must be the reverse of B's position seen from A, rotated.
// Returns nullopt when the detections are not a mutual pair (ids do not cross), are further apart
// in time than `max_time_difference`, or are too close to define a direction.
std::optional<RelativeHeading> MutualRelativeHeading(const RobotDetection& a_sees_b,
                                                     const RobotDetection& b_sees_a,
                                                     double max_time_difference = 0.05);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_RELATIVE_HEADING_H_

#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_DETECTION_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_DETECTION_H_

// The detection model is the project-wide RobotDetection (shared/core/robot_detection.h): the
// detector fills it, the agent uploads it, the merge engine and localization consume it. One
// definition only: two structs of that name in namespace fleetmap linked into one binary (the
// agent) would break the one-definition rule.
#include "shared/core/robot_detection.h"

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_DETECTION_H_

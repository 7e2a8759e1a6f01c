#ifndef FLEETMAP_ROBOT_AGENT_SLAM_INPUT_ORDER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_INPUT_ORDER_H_

#include <string>

namespace fleetmap {

// Every backend takes odometry and scans in time order: false, with a message naming `what`
// ("odometry", "scan"), when `timestamp` is not finite or older than `last_time`.
bool CheckInputTime(double timestamp, double last_time, const char* what, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_INPUT_ORDER_H_

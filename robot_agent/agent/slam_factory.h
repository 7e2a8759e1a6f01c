#ifndef FLEETMAP_ROBOT_AGENT_AGENT_SLAM_FACTORY_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_SLAM_FACTORY_H_

#include <memory>
#include <string>
#include <vector>

#include "robot_agent/agent/agent_config.h"
#include "robot_agent/slam/local_slam.h"

namespace fleetmap {

// The local SLAM backends this build offers (slam.algorithm values).
std::vector<std::string> AvailableSlamAlgorithms();

// The backend the configuration names, set up with its options; nullptr + `error` otherwise.
std::unique_ptr<LocalSlam> CreateLocalSlam(const SlamConfig& config, const std::string& robot_id,
                                           std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_SLAM_FACTORY_H_

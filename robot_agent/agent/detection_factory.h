#ifndef FLEETMAP_ROBOT_AGENT_AGENT_DETECTION_FACTORY_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_DETECTION_FACTORY_H_

#include <memory>
#include <string>

#include "robot_agent/agent/agent_config.h"
#include "robot_agent/agent/detection_stage.h"
#include "robot_agent/agent/sensor_source.h"

namespace fleetmap {

// The colour model from marker hues alone (no background knowledge): each marker is its hue
// +- half_width at saturations >= min_saturation.
ColourModel ColourModelFromHues(const std::map<std::string, double>& hues, double half_width,
                                double min_saturation);

// The detection stage the configuration asks for, given the opened source (the simulator
// supplies camera, markers and colours; a log takes them from detection:). nullptr + `error`
// (naming the field) when it cannot be built.
std::unique_ptr<DetectionStage> CreateDetectionStage(const AgentConfig& config,
                                                     const SensorSource& source,
                                                     std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_DETECTION_FACTORY_H_

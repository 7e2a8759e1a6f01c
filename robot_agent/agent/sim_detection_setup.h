#ifndef FLEETMAP_ROBOT_AGENT_AGENT_SIM_DETECTION_SETUP_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_SIM_DETECTION_SETUP_H_

#include <string>

#include "robot_agent/agent/detection_stage.h"
#include "robot_agent/sim/simulation.h"

namespace fleetmap {

struct SimColourLearningOptions {
  int views = 48;     // rendered training frames
  uint64_t seed = 7;  // pixel noise and exposure of the training frames
};

// The detector's setup for a simulated robot, out of the box: camera intrinsics and mount, marker
// geometry and laser noise from the scenario, and a colour model learnt at start from frames the
// simulator's own renderer draws in the scenario's world (its walls, lighting and same-coloured
// posters as background) with every robot's marker placed at known spots in front of the camera
// (the labels are exact). Learning from rendered frames rather than building the model from the
// marker hues alone gives the background histogram too, so that wall and poster colours near a
// marker hue are weighed against it. False + `error` when a marker could not be shown.
bool MakeSimDetectionSetup(const sim::Simulation& simulation,
                           const SimColourLearningOptions& options, DetectionSetup* setup,
                           std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_SIM_DETECTION_SETUP_H_

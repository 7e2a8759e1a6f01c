#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_SIM_COMMAND_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_SIM_COMMAND_H_

#include <string>

#include "robot_agent/localization/tool/sim_replay.h"

namespace fleetmap {

struct SimCommandOptions {
  std::string scenario_path;
  int runs = 50;
  uint32_t first_seed = 1;  // run i: filter seed first_seed + i, simulator seed scenario + i
  std::string mode = "both";  // collaborative | independent | both
  std::string plot_path;      // error vs time of the first run (PNG); empty = none
  double plot_max_error = 2.0;
  int trace_run = -1;  // prints the lost robot's errors of this run every 0.5 s
  double target_delay = 2.0;  // seconds from the first detection (the target)
  SimLocalizationOptions localization;
};

// `fleetmap-localize sim`: seeded runs of the Fig. 21-22 case with and without detections;
// prints per-run lines and the summary. Returns the process exit code.
int RunSimCommand(const SimCommandOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_SIM_COMMAND_H_

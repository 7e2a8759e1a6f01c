#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_LOG_COMMAND_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_LOG_COMMAND_H_

#include <optional>
#include <string>

#include "robot_agent/localization/mcl_localizer.h"

namespace fleetmap {

struct LogCommandOptions {
  std::string log_path;           // CARMEN log
  std::string map_path;           // ROS map YAML
  std::string out_path;           // trajectory file (fleetmap-eval's format)
  double max_range = 50.0;        // CARMEN readings at or above it are no-returns
  MclLocalizerOptions localizer;  // initial_pose unset: global localization
};

// `fleetmap-localize log`: the agent's localizer (MclLocalizer) over a CARMEN log in a known
// map, one pose per scan written to a trajectory file, with a summary (time to converge, speed).
// Returns the process exit code.
int RunLogCommand(const LogCommandOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_LOG_COMMAND_H_

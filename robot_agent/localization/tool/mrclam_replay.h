#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_MRCLAM_REPLAY_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_MRCLAM_REPLAY_H_

#include <functional>
#include <string>
#include <vector>

#include "robot_agent/localization/collaborative_update.h"
#include "robot_agent/localization/mcl.h"
#include "robot_agent/localization/pose_density.h"
#include "robot_agent/localization/tool/error_plot.h"
#include "robot_agent/localization/tool/mrclam_reader.h"

namespace fleetmap {

struct LocalizationReplayOptions {
  bool collaborative = false;
  // true: each filter starts from a Gaussian around the true start pose; false: uniform over
  // the arena (global localization).
  bool known_start = true;
  int particles = 1000;
  uint32_t seed = 1;
  double predict_interval = 0.1;  // seconds of odometry folded into one prediction
  double sample_interval = 1.0;   // seconds between error samples
  double max_time = 0.0;          // 0 = the whole log
  double detection_interval = 2.0;  // per observer/observed pair (DetectionGate)
  double lost_detection_interval = 0.5;  // ... when the observed robot is globally localizing
  // A converged estimate within this distance of the truth counts as localized.
  double converged_error = 0.3;
  LandmarkModelOptions landmarks;
  MclOptions mcl;
  DetectionSummaryOptions summary;
  DensityUpdateOptions density;
};

struct RobotReplayResult {
  std::string name;
  ErrorSeries position_error;  // (s, m)
  double mean_position_error = 0.0;
  double mean_heading_error = 0.0;   // radians
  double time_to_converge = -1.0;    // first sample localized (see converged_error); -1 never
  int detections_made = 0;           // robot-to-robot measurements by this robot
  int detections_used = 0;           // of those, fed to the observed robot's filter
};

struct ReplayResult {
  std::vector<RobotReplayResult> robots;
  double mean_position_error = 0.0;  // over all robots and samples
};

// Localizes every robot of the data set with landmarks (and, when collaborative, detections of
// each other). `progress` (may be empty) is called with the log time now and then.
ReplayResult ReplayMrclam(const MrclamDataset& dataset, const LocalizationReplayOptions& options,
                          const std::function<void(double)>& progress);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_MRCLAM_REPLAY_H_

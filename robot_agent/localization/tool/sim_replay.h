#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_SIM_REPLAY_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_SIM_REPLAY_H_

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/collaborative_update.h"
#include "robot_agent/localization/likelihood_field_model.h"
#include "robot_agent/localization/mcl.h"
#include "robot_agent/localization/pose_density.h"
#include "robot_agent/localization/tool/error_plot.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// The paper's Fig. 21-22 experiment in the simulator: robot 1 (index `lost_robot`) starts from a
// uniform belief over the known map, every other robot from a Gaussian around its true start.
// Each robot runs MCL on its simulated odometry and laser. Detections are simulated from the
// simulator's ground-truth visibility (camera field of view, occlusion), NOT from the camera
// pipeline: the true relative position plus Gaussian range/bearing noise of the size the
// detection pipeline measured on simulator frames (RMS 0.5 cm / 0.07 deg, see
// robot_agent/detection), with a matching covariance. When both robots see each other at the
// same tick the detection carries the relative heading too, as the pipeline's mutual
// detections do.
struct SimLocalizationOptions {
  bool detections = true;  // false: every robot localizes alone
  int lost_robot = 0;
  int particles = 5000;  // KLD maximum per robot
  uint32_t seed = 1;     // filter seed (the simulator's seed is the scenario's)
  double max_time = 0.0;  // seconds; 0 = the scenario's end
  // Known starts: Gaussian around the true start pose with these standard deviations.
  double start_position_std = 0.05;
  double start_heading_std = 2.0 * M_PI / 180.0;
  // Detection model.
  double detection_max_range = 8.0;  // the pipeline needs laser returns on the body
  double range_std = 0.01;
  double bearing_std = 0.1 * M_PI / 180.0;
  double relative_heading_std = 0.2 * M_PI / 180.0;
  double detection_interval = 2.0;  // DetectionGate, per ordered pair
  double lost_detection_interval = 0.5;  // ... when the observed robot is globally localizing
  // "Localized": the clustered estimate within these of the truth ...
  double position_tolerance = 0.2;
  double heading_tolerance = 5.0 * M_PI / 180.0;
  // ... at every laser update for this long (a stretch cut by the end of the run does not count).
  double hold_time = 5.0;
  LikelihoodFieldModelOptions laser;
  MclOptions mcl;
  DetectionSummaryOptions summary;
  DensityUpdateOptions density;
};

struct SimRobotResult {
  std::string name;
  ErrorSeries position_error;  // (s, m) at every laser update
  ErrorSeries heading_error;   // (s, rad)
  // Start of the first stretch localized for hold_time (see options); -1 never.
  double time_localized = -1.0;
  bool localized_at_end = false;
};

struct SimRunResult {
  std::vector<SimRobotResult> robots;
  double end_time = 0.0;
  // Of the detections of the lost robot by the others: the first tick one was visible within
  // range, and the first one that was applied to its belief (-1 when none).
  double first_visible_time = -1.0;
  double first_detection_time = -1.0;
  int detections_visible = 0;  // all ordered pairs, visible within range
  int detections_used = 0;     // applied to a belief
};

// Loads the known map for a world file: `<name>.world.yaml` -> `<name>.yaml` beside it, or the
// file itself when it is a plain map_server YAML.
bool LoadWorldMap(const std::string& world_path, OccupancyGrid* grid, std::string* error);

// One seeded run. False with `error` when the simulation cannot be created.
bool RunSimLocalization(const sim::Scenario& scenario, const sim::World& world,
                        const OccupancyGrid& map, const SimLocalizationOptions& options,
                        SimRunResult* result, std::string* error);

// First time t in the series (same times, in order) from which every (position, heading) error
// stays within tolerance for at least `hold` seconds; -1 when none.
double FirstLocalizedTime(const ErrorSeries& position, const ErrorSeries& heading,
                          double position_tolerance, double heading_tolerance, double hold);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_SIM_REPLAY_H_

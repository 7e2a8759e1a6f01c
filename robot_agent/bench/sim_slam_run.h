#ifndef FLEETMAP_ROBOT_AGENT_BENCH_SIM_SLAM_RUN_H_
#define FLEETMAP_ROBOT_AGENT_BENCH_SIM_SLAM_RUN_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/slam/local_slam.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

struct SimSlamRun {
  Trajectory estimate;      // one pose per scan, robot in the local map
  Trajectory ground_truth;  // robot in the world at the same timestamps
  std::map<int64_t, Submap> submaps;  // latest version of every submap
  // Every scan's returns in the robot frame, in the order of `ground_truth`: the walls can be
  // measured at the estimated poses without a grid's quantisation.
  std::vector<std::vector<Eigen::Vector2f>> returns;
  int64_t scans = 0;
  double slam_seconds = 0.0;  // wall time inside the backend
};

// Runs the first robot of a simulator scenario (in process, no files, camera off) through
// `slam`, feeding odometry and scans in time order. With `truth_map`, every scan is also
// inserted into it at its true pose (world frame): what a perfect SLAM would map.
bool RunSimulatedScenario(const std::string& scenario_path, LocalSlam* slam, SimSlamRun* run,
                          std::string* error, OccupancyGrid* truth_map = nullptr);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_BENCH_SIM_SLAM_RUN_H_

#ifndef FLEETMAP_ROBOT_AGENT_SLAM_POSE_GRAPH_2D_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_POSE_GRAPH_2D_H_

#include <string>
#include <vector>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// One measured relative pose: `to` seen from `from`, i.e. from_in_world^-1 * to_in_world.
struct PoseGraphConstraint {
  int from = 0;
  int to = 0;
  Rigid2d relative;
  double translation_sigma = 0.05;  // metres
  double rotation_sigma = 0.01;     // radians
  // Huber scale on the whitened residual (in sigmas); <= 0 means plain least squares. Loop
  // closures get one so that a wrong match cannot drag the whole graph.
  double robust_scale = 0.0;
};

struct PoseGraphOptions {
  int max_iterations = 20;
};

struct PoseGraphSummary {
  bool ok = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::string message;
};

// Least-squares 2D pose graph (Ceres, sparse Cholesky). `poses` holds the initial guess and
// receives the solution; poses flagged in `fixed` (same size, or empty = only pose 0 fixed) stay.
PoseGraphSummary OptimizePoseGraph(const std::vector<PoseGraphConstraint>& constraints,
                                   const std::vector<bool>& fixed, const PoseGraphOptions& options,
                                   std::vector<Rigid2d>* poses);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_POSE_GRAPH_2D_H_

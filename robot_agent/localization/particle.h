#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_PARTICLE_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_PARTICLE_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// One hypothesis of the robot's pose in the map frame.
struct Particle {
  Rigid2d robot_in_map;
  double weight = 0.0;
};

// The filter's summary of its belief.
struct PoseEstimate {
  Rigid2d robot_in_map;
  // Covariance of (x, y, theta); theta spread uses the circular variance.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  // True when the belief is unimodal and tight enough to act on (see ConvergenceOptions).
  bool converged = false;
  int particle_count = 0;
  // Share of the total weight in the cluster the estimate was taken from (1 for the plain
  // estimate over all particles) and the number of clusters found.
  double cluster_weight = 1.0;
  int cluster_count = 1;
};

struct ConvergenceOptions {
  double max_position_std = 0.3;  // metres, largest axis of the position covariance
  double max_heading_std = 0.2;   // radians
  // Clustered estimate (particle_clusters.h) only: the heaviest cluster must hold at least this
  // share of the weight. A few per cent on a far look-alike pose do not block convergence, two
  // comparable modes do.
  double min_cluster_weight = 0.9;
};

// Weighted mean and covariance of a particle set (weights need not be normalized).
PoseEstimate ComputeEstimate(const std::vector<Particle>& particles,
                             const ConvergenceOptions& options);

// Largest standard deviation of the position part of a covariance.
double MaxPositionStd(const Eigen::Matrix3d& covariance);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_PARTICLE_H_

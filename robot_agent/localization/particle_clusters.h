#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_PARTICLE_CLUSTERS_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_PARTICLE_CLUSTERS_H_

#include <cmath>
#include <vector>

#include "robot_agent/localization/particle.h"

namespace fleetmap {

// Particles are binned on an (x, y, heading) grid and bins that touch (26-neighbourhood, heading
// wrapping around) form one cluster, as AMCL does with its kd-tree. The mean of the whole set
// lies between the modes of a multi-modal belief; the heaviest cluster's mean is a pose the
// robot may actually be at.
struct ClusterOptions {
  double bin_size_xy = 0.5;                     // metres
  double bin_size_theta = 10.0 * M_PI / 180.0;  // radians
};

struct ParticleCluster {
  double weight = 0.0;       // share of the set's total weight
  std::vector<int> members;  // indices into the particle set
};

// Clusters ordered by weight, heaviest first. Empty for an empty set or zero total weight.
std::vector<ParticleCluster> ClusterParticles(const std::vector<Particle>& particles,
                                              const ClusterOptions& options);

// The estimate of the heaviest cluster: its mean and covariance, and `converged` when that
// cluster is tight (ConvergenceOptions) and holds at least min_cluster_weight of the weight.
PoseEstimate ComputeClusteredEstimate(const std::vector<Particle>& particles,
                                      const ConvergenceOptions& convergence,
                                      const ClusterOptions& options = ClusterOptions());

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_PARTICLE_CLUSTERS_H_

#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_POSE_DENSITY_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_POSE_DENSITY_H_

#include <optional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/particle.h"
#include "shared/core/rigid2d.h"
#include "shared/core/robot_detection.h"

namespace fleetmap {

// One Gaussian component of a PoseDensity.
struct PoseDensityKernel {
  double weight = 0.0;                                 // components' weights sum to 1
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();      // map frame, metres
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
  double heading = 0.0;                                // used only when has_heading
  double heading_variance = 0.0;
};

// The compact message robot m sends robot n after detecting it (eq. 15 of the paper, after Fox
// et al.'s collaborative MCL): the density of n's pose implied by m's belief and the detection,
// as a Gaussian mixture of at most a few dozen components. Without a relative heading the
// density says nothing about n's heading (uniform over [-pi, pi)).
struct PoseDensity {
  std::string observer_id;
  std::string observed_id;
  double timestamp = 0.0;
  bool has_heading = false;
  std::vector<PoseDensityKernel> kernels;

  // Density at a pose, per m^2 per radian.
  double Evaluate(const Rigid2d& robot_in_map) const;
  // Draws a pose (uniform heading when !has_heading). Requires non-empty kernels.
  Rigid2d Sample(std::mt19937& rng) const;
};

struct DetectionSummaryOptions {
  int max_kernels = 50;
  // Added in quadrature to the kernel bandwidth, so a handful of kernels still give a smooth
  // density (metres, radians).
  double min_bandwidth_xy = 0.03;
  double min_bandwidth_theta = 0.02;
  // Only a focused observer may speak (Fox et al.): otherwise its vague belief would be
  // multiplied into n's belief and later counted again when n's belief flows back. Focused =
  // the clustered estimate (particle_clusters.h) converged with these limits.
  double max_observer_position_std = 0.3;
  double max_observer_heading_std = 0.1;
};

// Observer side: the density of the observed robot's pose from the observer's particles and the
// detection. Returns nullopt when the observer is not focused or the detection is malformed
// (non-finite numbers, covariance not positive definite, empty particle set). `rng` selects
// which particles become kernels.
std::optional<PoseDensity> SummarizeDetection(const std::vector<Particle>& observer_particles,
                                              const RobotDetection& detection,
                                              const DetectionSummaryOptions& options,
                                              std::mt19937& rng);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_POSE_DENSITY_H_

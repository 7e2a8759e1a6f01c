#include "robot_agent/localization/landmark_model.h"

#include <algorithm>
#include <cmath>

#include "shared/core/rigid2d.h"

namespace fleetmap {

int LandmarkLogLikelihoods(const std::vector<LandmarkObservation>& observations,
                           const LandmarkMap& landmarks, const LandmarkModelOptions& options,
                           const std::vector<Particle>& particles,
                           std::vector<double>* log_likelihoods) {
  log_likelihoods->assign(particles.size(), 0.0);
  const double sr = std::max(options.sigma_range, 1e-4);
  const double sb = std::max(options.sigma_bearing, 1e-4);
  const double normalizer = 1.0 / (2.0 * M_PI * sr * sb);
  // The outlier density: uniform over 10 m of range and all bearings.
  const double outlier = options.outlier_probability / (10.0 * 2.0 * M_PI);
  const double inlier = 1.0 - options.outlier_probability;
  int used = 0;
  for (const LandmarkObservation& observation : observations) {
    const auto it = landmarks.find(observation.landmark_id);
    if (it == landmarks.end()) continue;
    ++used;
    const Eigen::Vector2d& landmark = it->second;
    for (size_t p = 0; p < particles.size(); ++p) {
      const Rigid2d& pose = particles[p].robot_in_map;
      const Eigen::Vector2d d = landmark - pose.translation();
      const double range_error = (observation.range - d.norm()) / sr;
      const double bearing_error =
          NormalizeAngle(observation.bearing - (std::atan2(d.y(), d.x()) - pose.rotation())) / sb;
      const double density =
          inlier * normalizer *
              std::exp(-0.5 * (range_error * range_error + bearing_error * bearing_error)) +
          outlier;
      (*log_likelihoods)[p] += options.log_likelihood_scale * std::log(density);
    }
  }
  return used;
}

}  // namespace fleetmap

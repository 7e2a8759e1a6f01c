#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_LANDMARK_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_LANDMARK_MODEL_H_

#include <map>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/particle.h"

namespace fleetmap {

// Range and bearing from the robot centre to a known landmark.
struct LandmarkObservation {
  int landmark_id = 0;
  double range = 0.0;    // metres
  double bearing = 0.0;  // radians, in the robot frame
};

// Landmark positions in the map frame, by id.
using LandmarkMap = std::map<int, Eigen::Vector2d>;

// Range/bearing perception model (Probabilistic Robotics, table 6.4 with known correspondence):
// independent Gaussian range and bearing errors, mixed with a small outlier term so that one
// misread barcode cannot wipe out the right particles.
struct LandmarkModelOptions {
  double sigma_range = 0.15;   // metres
  double sigma_bearing = 0.1;  // radians
  double outlier_probability = 0.05;
  double log_likelihood_scale = 1.0;
};

// Writes one log-likelihood per particle (resized) and returns the number of observations used
// (those with a known landmark id; unknown ids are ignored).
int LandmarkLogLikelihoods(const std::vector<LandmarkObservation>& observations,
                           const LandmarkMap& landmarks, const LandmarkModelOptions& options,
                           const std::vector<Particle>& particles,
                           std::vector<double>* log_likelihoods);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_LANDMARK_MODEL_H_

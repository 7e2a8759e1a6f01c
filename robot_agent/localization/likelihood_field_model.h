#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_LIKELIHOOD_FIELD_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_LIKELIHOOD_FIELD_MODEL_H_

#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/particle.h"
#include "shared/core/laser_scan.h"
#include "shared/core/likelihood_field.h"

namespace fleetmap {

// The likelihood-field laser model (Probabilistic Robotics, table 6.3): a beam end point's
// likelihood is a Gaussian in its distance to the nearest obstacle, mixed with a uniform term for
// unexplained readings. No-return beams carry no information and are skipped.
struct LikelihoodFieldModelOptions {
  int max_beams = 60;        // returns used per scan, evenly spaced over the valid ones
  double sigma_hit = 0.1;    // metres
  double z_hit = 0.9;
  double z_rand = 0.1;
  double max_range = 8.0;    // metres, scale of the uniform term
  // Beams are not independent (neighbours see the same wall); the sum of per-beam
  // log-likelihoods is multiplied by this to keep the posterior from collapsing too early.
  double log_likelihood_scale = 0.5;
};

class LikelihoodFieldModel {
 public:
  // Tabulates the per-cell log-likelihood once; `field` need not outlive the model.
  LikelihoodFieldModel(const LikelihoodField& field, const LikelihoodFieldModelOptions& options);

  const LikelihoodFieldModelOptions& options() const { return options_; }

  // Writes one log-likelihood per particle into `log_likelihoods` (resized) and returns the number
  // of beams used (0 when the scan has no returns: then every value is 0).
  // Not thread-safe: reuses an internal beam buffer to avoid allocating per update.
  int ComputeLogLikelihoods(const LaserScan& scan, const std::vector<Particle>& particles,
                            std::vector<double>* log_likelihoods);

  // Log-likelihood of one beam end point in the map frame (for tests and tools).
  float PointLogLikelihood(float x, float y) const;

 private:
  void SelectBeams(const LaserScan& scan);

  LikelihoodFieldModelOptions options_;
  float origin_x_ = 0.0f;
  float origin_y_ = 0.0f;
  float inverse_resolution_ = 1.0f;
  int width_ = 0;
  int height_ = 0;
  float outside_log_likelihood_ = 0.0f;
  std::vector<float> cell_log_likelihood_;  // row-major over the field
  std::vector<Eigen::Vector2f> beam_points_;  // selected end points in the robot frame
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_LIKELIHOOD_FIELD_MODEL_H_

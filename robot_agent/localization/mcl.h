#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_MCL_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_MCL_H_

#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/free_space.h"
#include "robot_agent/localization/landmark_model.h"
#include "robot_agent/localization/likelihood_field_model.h"
#include "robot_agent/localization/motion_model.h"
#include "robot_agent/localization/particle.h"
#include "robot_agent/localization/resampling.h"
#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// Augmented MCL (Probabilistic Robotics, table 8.3): short- and long-term averages of the
// measurement likelihood; when the short-term one falls below the long-term one the robot has
// probably been kidnapped, and random particles are injected in proportion.
struct RecoveryOptions {
  bool enabled = true;
  double alpha_slow = 0.001;
  double alpha_fast = 0.1;
  double max_injection_fraction = 0.25;  // of the particles drawn in one resampling
};

struct MclOptions {
  OdometryMotionModelOptions motion;
  KldOptions kld;
  RecoveryOptions recovery;
  ConvergenceOptions convergence;
  // Resample only when the effective sample size falls below this fraction of the particles
  // (resampling after every update throws diversity away).
  double resample_ess_fraction = 0.5;
  // Adaptive tempering: when one update would shrink the effective sample size below this
  // fraction of its value before the update, its log-likelihoods are scaled down until it does not. Sparse particles (a lost
  // robot) are never exactly at the true pose, and an untempered 60-beam likelihood lets whichever
  // hypothesis happens to have the luckiest particle win outright, even between two modes the map
  // cannot tell apart. The information held back is used by later updates. 0 disables.
  double min_update_ess_fraction = 0.5;
  // Added to a particle's log-likelihood when it sits outside the free space (inside a wall or
  // in unknown space). 0 disables the check.
  double off_map_log_likelihood = -3.0;
  uint32_t seed = 1;
};

// Monte Carlo localization of one robot in a known map. Deterministic for a fixed seed: all
// randomness comes from the filter's own generator. Not thread-safe.
class Mcl {
 public:
  Mcl(FreeSpace free_space, const MclOptions& options);

  const MclOptions& options() const { return options_; }
  const FreeSpace& free_space() const { return free_space_; }
  // A newer map (e.g. the next global map version): the particles stay where they are.
  void set_free_space(FreeSpace free_space) { free_space_ = std::move(free_space); }

  // Global localization: `count` particles (default max_particles) uniform over the free space
  // with uniform headings. Sets globally_localizing().
  void InitializeUniform(int count = 0);
  // Tracking: particles drawn from a Gaussian around `mean` ((x, y, theta) covariance).
  // Clears globally_localizing().
  void InitializeGaussian(const Rigid2d& mean, const Eigen::Matrix3d& covariance, int count = 0);

  // Moves every particle by a noisy copy of the odometry increment (robot frame, previous pose).
  void Predict(const Rigid2d& odometry_delta);

  // Multiplies the weights by exp(log_likelihoods) (one per particle); `terms` is the number of
  // readings they combine (beams, landmarks) so the recovery statistics are per reading.
  // Resamples when the weights have degenerated.
  void Correct(const std::vector<double>& log_likelihoods, int terms);
  void UpdateLaser(const LaserScan& scan, LikelihoodFieldModel& model);
  void UpdateLandmarks(const std::vector<LandmarkObservation>& observations,
                       const LandmarkMap& landmarks, const LandmarkModelOptions& options);

  // KLD-adaptive low-variance resampling with augmented-MCL injection; weights become uniform.
  void Resample();
  // The exponent the last Correct applied to its log-likelihoods (1 = untempered).
  double last_temper() const { return last_temper_; }

  // The heaviest particle cluster's mean and covariance (see particle_clusters.h).
  PoseEstimate Estimate() const;
  const std::vector<Particle>& particles() const { return particles_; }
  // For updates from outside (the collaborative detection update): callers may change weights
  // and poses, but must keep at least one particle.
  std::vector<Particle>& mutable_particles() { return particles_; }
  std::mt19937& rng() { return rng_; }
  // True from a uniform start until someone else's detection has located the robot
  // (ApplyPoseDensity clears it). A belief that converged on its own after a global start may sit
  // on a look-alike place, so a detection is trusted more than it (DensityUpdateOptions).
  bool globally_localizing() const { return globally_localizing_; }
  void set_globally_localizing(bool value) { globally_localizing_ = value; }
  // The current random-injection probability (0 when the filter is happy).
  double InjectionProbability() const;

 private:
  Particle RandomParticle();
  // Adaptive tempering over log_likelihoods_ (see MclOptions::min_update_ess_fraction).
  double ChooseTemper(double max_ll) const;
  double UpdatedEss(double temper, double max_ll) const;

  FreeSpace free_space_;
  const MclOptions options_;
  std::mt19937 rng_;
  std::vector<Particle> particles_;
  double w_slow_ = 0.0;
  double w_fast_ = 0.0;
  double last_temper_ = 1.0;
  bool globally_localizing_ = false;
  // Buffers reused across updates to avoid allocating.
  std::vector<double> model_log_likelihoods_;  // what the sensor model computed
  std::vector<double> log_likelihoods_;        // the same plus the map check
  std::vector<int> indices_;
  std::vector<int64_t> bin_scratch_;
  std::vector<Particle> next_particles_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_MCL_H_

#include "robot_agent/localization/mcl.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>

#include "robot_agent/localization/particle_clusters.h"

namespace fleetmap {

Mcl::Mcl(FreeSpace free_space, const MclOptions& options)
    : free_space_(std::move(free_space)), options_(options), rng_(options.seed) {}

Particle Mcl::RandomParticle() {
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  Particle particle;
  const Eigen::Vector2d position = free_space_.SamplePoint(rng_);
  particle.robot_in_map = Rigid2d(position, heading(rng_));
  particle.weight = 1.0;
  return particle;
}

void Mcl::InitializeUniform(int count) {
  if (count <= 0) count = std::max(1, options_.kld.max_particles);
  particles_.clear();
  for (int i = 0; i < count; ++i) particles_.push_back(RandomParticle());
  for (Particle& p : particles_) p.weight = 1.0 / count;
  w_slow_ = w_fast_ = 0.0;
  globally_localizing_ = true;
}

void Mcl::InitializeGaussian(const Rigid2d& mean, const Eigen::Matrix3d& covariance, int count) {
  if (count <= 0) count = std::max(1, options_.kld.max_particles);
  // A tiny diagonal keeps the factorization valid for a zero covariance.
  const Eigen::Matrix3d safe = covariance + 1e-12 * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d factor = Eigen::LLT<Eigen::Matrix3d>(safe).matrixL();
  std::normal_distribution<double> normal(0.0, 1.0);
  particles_.clear();
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d d = factor * Eigen::Vector3d(normal(rng_), normal(rng_), normal(rng_));
    particles_.push_back(Particle{
        Rigid2d(mean.translation() + d.head<2>(), mean.rotation() + d.z()), 1.0 / count});
  }
  w_slow_ = w_fast_ = 0.0;
  globally_localizing_ = false;
}

void Mcl::Predict(const Rigid2d& odometry_delta) {
  const OdometrySampler sampler(odometry_delta, options_.motion);
  for (Particle& p : particles_) p.robot_in_map = sampler.Sample(p.robot_in_map, rng_);
}

void Mcl::Correct(const std::vector<double>& log_likelihoods, int terms) {
  if (particles_.empty() || log_likelihoods.size() != particles_.size()) return;
  const bool check_map = options_.off_map_log_likelihood != 0.0;
  double total_prior = 0.0;
  for (const Particle& p : particles_) total_prior += p.weight;
  if (!(total_prior > 0.0)) total_prior = 1.0;
  double max_ll = -INFINITY;
  double quality = 0.0;
  log_likelihoods_.resize(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i) {
    double ll = log_likelihoods[i];
    if (check_map && !free_space_.IsFree(particles_[i].robot_in_map.translation())) {
      ll += options_.off_map_log_likelihood;
    }
    log_likelihoods_[i] = ll;
    max_ll = std::max(max_ll, ll);
    if (terms > 0) quality += particles_[i].weight / total_prior * std::exp(ll / terms);
  }
  if (!std::isfinite(max_ll)) return;  // nothing usable: keep the prior
  last_temper_ = ChooseTemper(max_ll);
  double total = 0.0;
  for (size_t i = 0; i < particles_.size(); ++i) {
    particles_[i].weight *= std::exp(last_temper_ * (log_likelihoods_[i] - max_ll));
    total += particles_[i].weight;
  }
  if (!(total > 0.0)) {
    // Every particle with prior weight was ruled out: restart from the likelihood alone.
    for (size_t i = 0; i < particles_.size(); ++i) {
      particles_[i].weight = std::exp(log_likelihoods_[i] - max_ll);
      total += particles_[i].weight;
    }
  }
  for (Particle& p : particles_) p.weight /= total;
  if (terms > 0 && std::isfinite(quality)) {
    if (w_slow_ <= 0.0) w_slow_ = w_fast_ = quality;
    w_slow_ += options_.recovery.alpha_slow * (quality - w_slow_);
    w_fast_ += options_.recovery.alpha_fast * (quality - w_fast_);
  }
  if (EffectiveSampleSize(particles_) <
      options_.resample_ess_fraction * static_cast<double>(particles_.size())) {
    Resample();
  }
}

double Mcl::UpdatedEss(double temper, double max_ll) const {
  double total = 0.0, squares = 0.0;
  for (size_t i = 0; i < particles_.size(); ++i) {
    const double w = particles_[i].weight * std::exp(temper * (log_likelihoods_[i] - max_ll));
    total += w;
    squares += w * w;
  }
  return squares > 0.0 ? total * total / squares : 0.0;
}

double Mcl::ChooseTemper(double max_ll) const {
  // Relative to the prior's own effective size: the prior may already be uneven when the last
  // update did not trigger a resampling.
  const double target = options_.min_update_ess_fraction * EffectiveSampleSize(particles_);
  if (target <= 0.0 || UpdatedEss(1.0, max_ll) >= target) return 1.0;
  // The effective sample size falls as the exponent grows: bisect for the largest exponent that
  // keeps it above the target.
  double lo = 0.0, hi = 1.0;
  for (int iteration = 0; iteration < 12; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (UpdatedEss(mid, max_ll) >= target ? lo : hi) = mid;
  }
  return std::max(lo, 1e-4);
}

void Mcl::UpdateLaser(const LaserScan& scan, LikelihoodFieldModel& model) {
  const int beams = model.ComputeLogLikelihoods(scan, particles_, &model_log_likelihoods_);
  if (beams > 0) Correct(model_log_likelihoods_, beams);
}

void Mcl::UpdateLandmarks(const std::vector<LandmarkObservation>& observations,
                          const LandmarkMap& landmarks, const LandmarkModelOptions& options) {
  const int used = LandmarkLogLikelihoods(observations, landmarks, options, particles_,
                                          &model_log_likelihoods_);
  if (used > 0) Correct(model_log_likelihoods_, used);
}

double Mcl::InjectionProbability() const {
  if (!options_.recovery.enabled || w_slow_ <= 0.0) return 0.0;
  return std::clamp(1.0 - w_fast_ / w_slow_, 0.0, options_.recovery.max_injection_fraction);
}

void Mcl::Resample() {
  if (particles_.empty()) return;
  // KLD: count the bins the resampled set would occupy at the current size, then draw as many
  // particles as that many bins need.
  LowVarianceSelect(particles_, static_cast<int>(particles_.size()), rng_, &indices_);
  const int bins = CountOccupiedBins(particles_, indices_, options_.kld, &bin_scratch_);
  const int count = KldSampleCount(bins, options_.kld);
  LowVarianceSelect(particles_, count, rng_, &indices_);
  const double inject = InjectionProbability();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  next_particles_.clear();
  for (const int index : indices_) {
    if (inject > 0.0 && unit(rng_) < inject) {
      next_particles_.push_back(RandomParticle());
    } else {
      next_particles_.push_back(particles_[static_cast<size_t>(index)]);
    }
  }
  const double weight = 1.0 / static_cast<double>(next_particles_.size());
  for (Particle& p : next_particles_) p.weight = weight;
  particles_.swap(next_particles_);
  // Unlike AMCL we do not reset the averages after an injection: restarting the slow average
  // at the kidnapped robot's poor likelihood would stop the injection before it found the robot.
}

PoseEstimate Mcl::Estimate() const {
  return ComputeClusteredEstimate(particles_, options_.convergence);
}

}  // namespace fleetmap

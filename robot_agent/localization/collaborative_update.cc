#include "robot_agent/localization/collaborative_update.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "robot_agent/localization/resampling.h"

namespace fleetmap {
namespace {

// Kernel density estimate of a particle belief (per m^2 per radian), with a bandwidth that
// follows the belief's own spread (Scott's rule in 3 dimensions), so it is tight for a focused
// belief and wide for a lost one.
class BeliefDensity {
 public:
  BeliefDensity(const std::vector<Particle>& particles, int max_samples, std::mt19937& rng) {
    ConvergenceOptions any;
    const PoseEstimate estimate = ComputeEstimate(particles, any);
    std::vector<int> indices;
    LowVarianceSelect(particles, std::min<int>(max_samples, particles.size()), rng, &indices);
    for (const int i : indices) samples_.push_back(particles[static_cast<size_t>(i)].robot_in_map);
    const double factor = std::pow(static_cast<double>(samples_.size()), -1.0 / 7.0);
    const double sxy = std::sqrt(std::max(estimate.covariance(0, 0), estimate.covariance(1, 1)));
    const double st = std::sqrt(std::min(estimate.covariance(2, 2), M_PI * M_PI / 3.0));
    hxy_ = std::max(0.02, sxy * factor);
    ht_ = std::max(0.02, st * factor);
  }

  double Evaluate(const Rigid2d& pose) const {
    const double inv_xy = 1.0 / (hxy_ * hxy_);
    const double inv_t = 1.0 / (ht_ * ht_);
    double sum = 0.0;
    for (const Rigid2d& s : samples_) {
      const double d2 = (pose.translation() - s.translation()).squaredNorm() * inv_xy;
      if (d2 > 40.0) continue;
      const double dt = NormalizeAngle(pose.rotation() - s.rotation());
      sum += std::exp(-0.5 * (d2 + dt * dt * inv_t));
    }
    const double normalizer = std::pow(2.0 * M_PI, 1.5) * hxy_ * hxy_ * ht_;
    return sum / (normalizer * static_cast<double>(samples_.size()));
  }

 private:
  std::vector<Rigid2d> samples_;
  double hxy_ = 0.1;
  double ht_ = 0.1;
};

// The weighted mean of the kernel centres (map frame).
Eigen::Vector2d KernelMean(const PoseDensity& density) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const PoseDensityKernel& k : density.kernels) mean += k.weight * k.mean;
  return mean;
}

// Standard deviation of the kernel centres (metres, largest over x and y).
double KernelSpread(const PoseDensity& density) {
  const Eigen::Vector2d mean = KernelMean(density);
  Eigen::Vector2d variance = Eigen::Vector2d::Zero();
  for (const PoseDensityKernel& k : density.kernels) {
    variance += k.weight * (k.mean - mean).cwiseAbs2();
  }
  return std::sqrt(variance.maxCoeff());
}

}  // namespace

bool ApplyPoseDensity(const PoseDensity& density, const DensityUpdateOptions& options, Mcl* mcl) {
  std::vector<Particle>& particles = mcl->mutable_particles();
  if (density.kernels.empty() || particles.empty()) return false;
  const FreeSpace& space = mcl->free_space();
  const double uniform = 1.0 / (std::max(space.area(), 1e-6) * 2.0 * M_PI);
  const double eps = std::clamp(options.outlier_probability, 0.0, 1.0);

  double total_prior = 0.0;
  for (const Particle& p : particles) total_prior += p.weight;
  if (!(total_prior > 0.0)) return false;

  const bool trust_detection =
      mcl->globally_localizing() && KernelSpread(density) <= options.lost_floor_max_spread;
  const double floor = std::clamp(trust_detection ? options.lost_belief_floor_probability
                                                  : options.belief_floor_probability,
                                  0.0, 1.0);
  const double phi = std::clamp(options.injection_fraction, 0.0, 0.95);
  // Sized from the filter's maximum, not its current count: a robot that converged (wrongly) on
  // its own may be down to a few hundred particles, and a detection without heading needs its
  // samples spread over all headings finely enough for the laser to find the right one.
  const size_t budget =
      std::max(particles.size(),
               static_cast<size_t>(std::max(0, mcl->options().kld.max_particles)));
  const int count = static_cast<int>(std::round(phi * static_cast<double>(budget)));

  // The posterior is bel' * q' with bel' = (1 - floor) bel + floor u and q' = (1 - eps) q + eps u.
  // Its first part, (1 - floor) bel q', is estimated twice and the two estimates are averaged
  // with weights (1 - phi) and phi: by the old particles (samples of bel, weighted by q') and by
  // fresh samples of q (weighted by a kernel estimate of bel times q' / q). Its second part,
  // floor u q', is seen only by the fresh samples.
  const double old_share = count > 0 ? 1.0 - phi : 1.0;
  std::vector<double> old_weights(particles.size());
  double old_agreeing = 0.0;  // the part of the old particles' weight the detection itself gave
  for (size_t i = 0; i < particles.size(); ++i) {
    const double q = density.Evaluate(particles[i].robot_in_map);
    const double prior = old_share * (1.0 - floor) * particles[i].weight / total_prior;
    old_weights[i] = prior * ((1.0 - eps) * q + eps * uniform);
    old_agreeing += prior * (1.0 - eps) * q;
  }
  std::vector<Particle> fresh;
  if (count > 0) {
    const BeliefDensity belief(particles, 1000, mcl->rng());
    for (int j = 0; j < count; ++j) {
      Rigid2d pose = density.Sample(mcl->rng());
      for (int attempt = 0; attempt < 10 && !space.IsFree(pose.translation()); ++attempt) {
        pose = density.Sample(mcl->rng());
      }
      // Samples that stay outside the free space keep weight 0 (the belief is 0 there).
      const double q = density.Evaluate(pose);
      if (!space.IsFree(pose.translation()) || !(q > 0.0)) continue;
      const double prior = phi * (1.0 - floor) * belief.Evaluate(pose) + floor * uniform;
      fresh.push_back(Particle{pose, prior * ((1.0 - eps) * q + eps * uniform) / q / count});
    }
  }
  // The detection confirmed the belief when the old particles, not the fresh samples, carry
  // most of the posterior by agreeing with it (old particles far from it keep some weight too,
  // as if it were an outlier), and the estimate it leaves lies where the detection says: in a
  // simulated run the old particles had carried the posterior while the estimate stayed on a
  // look-alike place 45 m off, and the robot, no longer globally localizing, waited 4 s for the
  // next detection (docs/BENCHMARKS.md, issue 10). Only then does the robot stop counting as
  // globally localizing.
  double old_total = 0.0, fresh_total = 0.0;
  for (size_t i = 0; i < particles.size(); ++i) {
    particles[i].weight = old_weights[i];
    old_total += old_weights[i];
  }
  for (const Particle& p : fresh) fresh_total += p.weight;
  particles.insert(particles.end(), fresh.begin(), fresh.end());
  mcl->Resample();
  if (old_agreeing > options.confirmation_share * (old_total + fresh_total)) {
    const PoseEstimate estimate = mcl->Estimate();
    if ((estimate.robot_in_map.translation() - KernelMean(density)).norm() <=
        options.confirmation_distance) {
      mcl->set_globally_localizing(false);
    }
  }
  return true;
}

bool DetectionGate::Allow(const std::string& observer_id, const std::string& observed_id,
                          double timestamp, bool observed_lost) {
  const auto key = std::make_pair(observer_id, observed_id);
  const auto it = last_use_.find(key);
  const double interval =
      observed_lost ? std::min(min_interval_, lost_min_interval_) : min_interval_;
  if (it != last_use_.end() && timestamp - it->second < interval && timestamp >= it->second) {
    return false;
  }
  last_use_[key] = timestamp;
  return true;
}

}  // namespace fleetmap

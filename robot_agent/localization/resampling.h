#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_RESAMPLING_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_RESAMPLING_H_

#include <cstdint>
#include <random>
#include <vector>

#include "robot_agent/localization/particle.h"

namespace fleetmap {

// Low-variance (systematic) resampling, Probabilistic Robotics table 4.4: one random offset, then
// `count` evenly spaced pointers into the cumulative weights. Writes the chosen particle indices
// (non-decreasing) into `indices`. Weights need not be normalized; all-zero weights select
// uniformly.
void LowVarianceSelect(const std::vector<Particle>& particles, int count, std::mt19937& rng,
                       std::vector<int>* indices);

// Effective sample size 1 / sum(w^2) of normalized weights.
double EffectiveSampleSize(const std::vector<Particle>& particles);

// KLD-sampling (Fox 2003): the number of samples needed so that, with probability 1 - delta, the
// K-L divergence between the sample-based and the true posterior stays below epsilon, given that
// the samples fall into `occupied_bins` histogram bins.
struct KldOptions {
  int min_particles = 200;
  int max_particles = 5000;
  double epsilon = 0.05;
  double z_quantile = 2.326;  // upper 1 - delta quantile of the normal, delta = 0.01
  double bin_size_xy = 0.5;   // metres
  double bin_size_theta = 10.0 * M_PI / 180.0;
};
int KldSampleCount(int occupied_bins, const KldOptions& options);

// Number of distinct (x, y, theta) bins among `particles[indices[i]]`. `scratch` avoids
// allocating per call.
int CountOccupiedBins(const std::vector<Particle>& particles, const std::vector<int>& indices,
                      const KldOptions& options, std::vector<int64_t>* scratch);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_RESAMPLING_H_

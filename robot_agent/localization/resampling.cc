#include "robot_agent/localization/resampling.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

void LowVarianceSelect(const std::vector<Particle>& particles, int count, std::mt19937& rng,
                       std::vector<int>* indices) {
  indices->clear();
  if (particles.empty() || count <= 0) return;
  double total = 0.0;
  for (const Particle& p : particles) total += p.weight;
  const int n = static_cast<int>(particles.size());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double offset = unit(rng) / count;
  if (!(total > 0.0) || !std::isfinite(total)) {
    for (int m = 0; m < count; ++m) {
      indices->push_back(std::min(n - 1, static_cast<int>((offset + double(m) / count) * n)));
    }
    return;
  }
  const double step = total / count;
  double pointer = offset * total;
  double cumulative = particles[0].weight;
  int i = 0;
  for (int m = 0; m < count; ++m) {
    while (pointer > cumulative && i < n - 1) {
      ++i;
      cumulative += particles[static_cast<size_t>(i)].weight;
    }
    indices->push_back(i);
    pointer += step;
  }
}

double EffectiveSampleSize(const std::vector<Particle>& particles) {
  double total = 0.0, squares = 0.0;
  for (const Particle& p : particles) {
    total += p.weight;
    squares += p.weight * p.weight;
  }
  if (!(squares > 0.0)) return 0.0;
  return total * total / squares;
}

int KldSampleCount(int occupied_bins, const KldOptions& options) {
  const int lo = std::max(1, options.min_particles);
  const int hi = std::max(lo, options.max_particles);
  if (occupied_bins <= 1) return lo;
  const double k = occupied_bins - 1;
  const double a = 2.0 / (9.0 * k);
  const double b = 1.0 - a + std::sqrt(a) * options.z_quantile;
  const double n = k / (2.0 * std::max(options.epsilon, 1e-6)) * b * b * b;
  return std::clamp(static_cast<int>(std::ceil(std::min(n, 1e9))), lo, hi);
}

int CountOccupiedBins(const std::vector<Particle>& particles, const std::vector<int>& indices,
                      const KldOptions& options, std::vector<int64_t>* scratch) {
  scratch->clear();
  const double inv_xy = 1.0 / options.bin_size_xy;
  const double inv_theta = 1.0 / options.bin_size_theta;
  int previous = -1;
  for (const int index : indices) {
    if (index == previous) continue;  // indices are non-decreasing: skip repeats cheaply
    previous = index;
    const Rigid2d& pose = particles[static_cast<size_t>(index)].robot_in_map;
    // 21 bits each for x and y (+-1e6 bins), 9 bits for theta.
    const int64_t ix = static_cast<int64_t>(std::floor(pose.x() * inv_xy)) + (1 << 20);
    const int64_t iy = static_cast<int64_t>(std::floor(pose.y() * inv_xy)) + (1 << 20);
    const int64_t it = static_cast<int64_t>(std::floor((pose.rotation() + M_PI) * inv_theta));
    scratch->push_back(((ix & 0x1FFFFF) << 30) | ((iy & 0x1FFFFF) << 9) | (it & 0x1FF));
  }
  std::sort(scratch->begin(), scratch->end());
  return static_cast<int>(std::unique(scratch->begin(), scratch->end()) - scratch->begin());
}

}  // namespace fleetmap

#include "robot_agent/localization/particle_clusters.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace fleetmap {
namespace {

struct BinKey {
  int64_t x = 0;
  int64_t y = 0;
  int64_t theta = 0;
};

// Bins far beyond any map (|coordinate| > 2^20 bins) alias; harmless for clustering.
int64_t Pack(int64_t x, int64_t y, int64_t theta) {
  return ((x & 0x1FFFFF) << 42) | ((y & 0x1FFFFF) << 21) | (theta & 0x1FFFFF);
}

}  // namespace

std::vector<ParticleCluster> ClusterParticles(const std::vector<Particle>& particles,
                                              const ClusterOptions& options) {
  std::vector<ParticleCluster> clusters;
  double total = 0.0;
  for (const Particle& p : particles) total += p.weight;
  if (particles.empty() || !(total > 0.0)) return clusters;
  const double xy = std::max(options.bin_size_xy, 1e-6);
  const int64_t theta_bins =
      std::max<int64_t>(1, static_cast<int64_t>(std::ceil(2.0 * M_PI / options.bin_size_theta)));
  const double theta_size = 2.0 * M_PI / static_cast<double>(theta_bins);

  // Bin -> index into `bins`; each bin lists its particles.
  std::unordered_map<int64_t, int> bin_of_key;
  std::vector<BinKey> keys;
  std::vector<std::vector<int>> bins;
  for (size_t i = 0; i < particles.size(); ++i) {
    const Rigid2d& pose = particles[i].robot_in_map;
    if (!pose.translation().allFinite() || !std::isfinite(pose.rotation())) continue;
    BinKey key;
    key.x = static_cast<int64_t>(std::floor(pose.translation().x() / xy));
    key.y = static_cast<int64_t>(std::floor(pose.translation().y() / xy));
    key.theta = static_cast<int64_t>(std::floor((NormalizeAngle(pose.rotation()) + M_PI) /
                                                theta_size)) % theta_bins;
    const auto [it, inserted] =
        bin_of_key.emplace(Pack(key.x, key.y, key.theta), static_cast<int>(bins.size()));
    if (inserted) {
      keys.push_back(key);
      bins.emplace_back();
    }
    bins[static_cast<size_t>(it->second)].push_back(static_cast<int>(i));
  }

  // Connected components over touching bins (flood fill with an explicit stack).
  std::vector<int> label(bins.size(), -1);
  std::vector<int> stack;
  for (size_t seed = 0; seed < bins.size(); ++seed) {
    if (label[seed] >= 0) continue;
    ParticleCluster cluster;
    const int id = static_cast<int>(clusters.size());
    label[seed] = id;
    stack.assign(1, static_cast<int>(seed));
    while (!stack.empty()) {
      const int bin = stack.back();
      stack.pop_back();
      for (const int member : bins[static_cast<size_t>(bin)]) {
        cluster.members.push_back(member);
        cluster.weight += particles[static_cast<size_t>(member)].weight / total;
      }
      const BinKey& k = keys[static_cast<size_t>(bin)];
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dt = -1; dt <= 1; ++dt) {
            const int64_t theta = (k.theta + dt + theta_bins) % theta_bins;
            const auto it = bin_of_key.find(Pack(k.x + dx, k.y + dy, theta));
            if (it == bin_of_key.end() || label[static_cast<size_t>(it->second)] >= 0) continue;
            label[static_cast<size_t>(it->second)] = id;
            stack.push_back(it->second);
          }
        }
      }
    }
    clusters.push_back(std::move(cluster));
  }
  std::stable_sort(clusters.begin(), clusters.end(),
                   [](const ParticleCluster& a, const ParticleCluster& b) {
                     return a.weight > b.weight;
                   });
  return clusters;
}

PoseEstimate ComputeClusteredEstimate(const std::vector<Particle>& particles,
                                      const ConvergenceOptions& convergence,
                                      const ClusterOptions& options) {
  const std::vector<ParticleCluster> clusters = ClusterParticles(particles, options);
  if (clusters.empty()) return ComputeEstimate(particles, convergence);
  std::vector<Particle> heaviest;
  heaviest.reserve(clusters.front().members.size());
  for (const int i : clusters.front().members) {
    heaviest.push_back(particles[static_cast<size_t>(i)]);
  }
  PoseEstimate estimate = ComputeEstimate(heaviest, convergence);
  estimate.particle_count = static_cast<int>(particles.size());
  estimate.cluster_weight = clusters.front().weight;
  estimate.cluster_count = static_cast<int>(clusters.size());
  estimate.converged =
      estimate.converged && estimate.cluster_weight >= convergence.min_cluster_weight;
  return estimate;
}

}  // namespace fleetmap

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "robot_agent/slam/particle_filter.h"
#include "shared/matching/point_filter.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

testing::SegmentWorld Room() {
  testing::SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(-6.0, -4.0), Eigen::Vector2d(8.0, 4.0));
  testing::AddBox(Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.5, 1.4), &world);
  testing::AddBox(Eigen::Vector2d(-2.0, -2.0), Eigen::Vector2d(-1.7, -1.2), &world);
  testing::AddBox(Eigen::Vector2d(4.0, -1.0), Eigen::Vector2d(4.4, -0.2), &world);
  return world;
}

ParticleScan ScanAt(const Rigid2d& pose, bool with_points = true) {
  const LaserScan scan = testing::SimulateScan(Room(), pose, 361, -M_PI, M_PI / 180, 15.0f);
  ParticleScan out;
  if (with_points) out.match_points = VoxelFilter(ToPointsInRobotFrame(scan), 0.1f);
  out.weight_points = out.match_points;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!std::isfinite(scan.ranges[i])) continue;
    const double a = scan.angle(static_cast<int>(i));
    out.ray_ends.emplace_back(scan.ranges[i] * std::cos(a), scan.ranges[i] * std::sin(a));
    out.ray_hits.push_back(1);
  }
  return out;
}

TEST(ParticleFilterTest, NoResamplingWhileWeightsAreEven) {
  ParticleFilterOptions options;
  options.particles = 20;
  ParticleFilter filter(options, nullptr);
  filter.Initialize(Rigid2d(), ScanAt(Rigid2d()));
  // A scan without match points carries no evidence: every particle gets the same increment.
  for (int step = 1; step <= 3; ++step) {
    filter.Update(Rigid2d(0.5, 0.0, 0.0), Rigid2d(0.5, 0.0, 0.0), ScanAt(Rigid2d(0.5 * step, 0.0, 0.0), false));
    EXPECT_NEAR(filter.last_effective_sample_size(), 20.0, 1e-9);
    EXPECT_FALSE(filter.last_resampled());
  }
  EXPECT_EQ(filter.resamplings(), 0);
  for (const Particle& particle : filter.particles()) EXPECT_NEAR(std::exp(particle.log_weight), 0.05, 1e-12);
}

TEST(ParticleFilterTest, ResamplesWhenWeightsDegenerate) {
  ParticleFilterOptions options;
  options.particles = 20;
  options.proposal = ParticleProposal::kMotionModel;
  options.srr = 0.5;  // wide motion noise: the scan separates good particles from bad ones
  options.str = 0.5;
  options.observation_gain = 1.0;
  ParticleFilter filter(options, nullptr);
  filter.Initialize(Rigid2d(), ScanAt(Rigid2d()));
  filter.Update(Rigid2d(1.0, 0.0, 0.0), Rigid2d(1.0, 0.0, 0.0), ScanAt(Rigid2d(1.0, 0.0, 0.0)));
  EXPECT_LT(filter.last_effective_sample_size(), 10.0);
  EXPECT_TRUE(filter.last_resampled());
  EXPECT_EQ(filter.resamplings(), 1);
  // After resampling the weights are even again.
  for (const Particle& particle : filter.particles()) EXPECT_NEAR(std::exp(particle.log_weight), 0.05, 1e-12);
}

// A hall longer than the scans reach, with a lattice of pillars so every pose is constrained.
testing::SegmentWorld Corridor() {
  testing::SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(-2.0, -4.0), Eigen::Vector2d(80.0, 4.0));
  for (double x = 0.0; x < 80.0; x += 1.7) {
    for (double y = -3.0; y < 3.5; y += 1.9) {
      if (std::abs(y - 0.0) < 0.5) continue;  // keep the robot's lane free
      testing::AddBox(Eigen::Vector2d(x, y), Eigen::Vector2d(x + 0.25, y + 0.2), &world);
    }
  }
  return world;
}

ParticleScan CorridorScan(const Rigid2d& pose) {
  const LaserScan scan = testing::SimulateScan(Corridor(), pose, 361, -M_PI, M_PI / 180, 4.0f);
  ParticleScan out;
  out.match_points = VoxelFilter(ToPointsInRobotFrame(scan), 0.1f);
  out.weight_points = out.match_points;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!std::isfinite(scan.ranges[i])) continue;
    const double a = scan.angle(static_cast<int>(i));
    out.ray_ends.emplace_back(scan.ranges[i] * std::cos(a), scan.ranges[i] * std::sin(a));
    out.ray_hits.push_back(1);
  }
  return out;
}

TEST(ParticleFilterTest, ParticlesShareUnchangedMapTiles) {
  ParticleFilterOptions options;
  options.particles = 10;
  options.resample_threshold = 2.0;  // resample at every update: copies share all tiles
  ParticleFilter filter(options, nullptr);
  filter.Initialize(Rigid2d(), CorridorScan(Rigid2d()));
  const size_t one_map = filter.UniqueTileBytes();
  EXPECT_EQ(filter.TotalTileBytes(), 10 * one_map);
  Rigid2d truth;
  for (int step = 0; step < 70; ++step) {
    truth = truth * Rigid2d(1.0, 0.0, 0.0);
    filter.Update(Rigid2d(1.0, 0.0, 0.0), Rigid2d(1.0, 0.0, 0.0), CorridorScan(truth));
  }
  // One more update without resampling: every particle clones the tiles it writes.
  truth = truth * Rigid2d(1.0, 0.0, 0.0);
  filter.Update(Rigid2d(1.0, 0.0, 0.0), Rigid2d(1.0, 0.0, 0.0), CorridorScan(truth));
  const size_t unique = filter.UniqueTileBytes(), total = filter.TotalTileBytes();
  std::cout << "map tiles after 71 updates: " << unique / 1024 << " KiB unique, " << total / 1024
            << " KiB referenced by 10 particles\n";
  // Particles differ only where their lineages diverged (the last ~2N updates), not in the
  // whole map.
  EXPECT_LT(unique, total / 2);
  EXPECT_THAT(filter.best().pose, testing::IsNearPose(truth, 0.5, 0.03));
}

}  // namespace
}  // namespace fleetmap

#include "tests/slam/particle_test_loop.h"

#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "tests/slam/slam_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

std::vector<Rigid2d> LoopPoses() {
  return PathPoses({{-9.0, -6.5}, {9.0, -6.5}, {9.0, 6.5}, {-9.0, 6.5}, {-9.0, -6.5}, {0.0, -6.5}},
                   /*turn_after_last=*/false);
}

void RunLoop(LocalSlam* slam, const std::vector<Rigid2d>& truth, const std::vector<Rigid2d>& odometry,
             const std::function<void()>& after_scan) {
  const SegmentWorld world = CorridorRing();
  std::mt19937 rng(7);
  std::normal_distribution<float> range_noise(0.0f, 0.005f);
  std::string error;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double t = 0.1 * static_cast<double>(i);
    LaserScan scan = SimulateScan(world, truth[i], 181, static_cast<float>(-M_PI / 2),
                                           static_cast<float>(M_PI / 180), 10.0f);
    for (float& r : scan.ranges) {
      if (std::isfinite(r)) r += range_noise(rng);
    }
    scan.timestamp = t;
    ASSERT_TRUE(slam->AddOdometry({t, odometry[i]}, &error)) << error;
    ASSERT_TRUE(slam->AddScan(scan, &error)) << error;
    if (after_scan) after_scan();
  }
}

ParticleSlamOptions SmallRbpf(unsigned seed, int threads) {
  ParticleSlamOptions options = ParticleSlamOptions::Rbpf();
  options.filter.particles = 10;
  options.filter.seed = seed;
  options.threads = threads;
  options.max_range = 10.0f;
  return options;
}

double EndError(const LocalSlam& slam, const std::vector<Rigid2d>& truth) {
  const Rigid2d end_truth = truth.front().inverse() * truth.back();
  return (slam.CurrentPose().translation() - end_truth.translation()).norm();
}

}  // namespace fleetmap::testing

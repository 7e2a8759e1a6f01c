#include "robot_agent/slam/particle_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "robot_agent/slam/particle_proposal.h"
#include "shared/matching/degeneracy.h"
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

// A filter input from a simulated scan: points matched and weighted (one per 10 cm voxel, or
// none), and every return as a ray hit.
ParticleScan ToParticleScan(const LaserScan& scan, bool with_points = true) {
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

ParticleScan ScanAt(const Rigid2d& pose, bool with_points = true) {
  return ToParticleScan(testing::SimulateScan(Room(), pose, 361, -M_PI, M_PI / 180, 15.0f), with_points);
}

// A plain corridor (no end in the laser's 8 m) seen from x = 0, then from x = 1 m: along the
// axis the scan says nothing, so both proposals keep the predicted translation there instead of
// letting the match slide (here, with every return matched, the ICP pulled it 0.1-0.2 m back
// towards the map's wall ends) or sampled noise walk. Across the corridor the scan decides.
TEST(ParticleFilterTest, ProposalsKeepThePredictionAlongAPlainCorridor) {
  const testing::SegmentWorld corridor = {
      {Eigen::Vector2d(-1.0, -1.0), Eigen::Vector2d(40.0, -1.0)},
      {Eigen::Vector2d(-1.0, 1.0), Eigen::Vector2d(40.0, 1.0)}};
  auto scan_at = [&](const Rigid2d& pose) {
    const LaserScan scan = testing::SimulateScan(corridor, pose, 181, -M_PI / 2, M_PI / 180, 8.0f);
    ParticleScan out = ToParticleScan(scan);
    out.normal_scatter = NormalScatter(ToPointsInRobotFrame(scan));
    return out;
  };
  for (ParticleProposal proposal :
       {ParticleProposal::kImprovedProposal, ParticleProposal::kMotionModel}) {
    ParticleFilterOptions options;
    options.proposal = proposal;
    SharedTileGrid map(options.grid, 1);
    const ParticleScan first = scan_at(Rigid2d());
    map.InsertRays(Eigen::Vector2d::Zero(), first.ray_ends, first.ray_hits);
    // The robot is 3 cm off the centre line; odometry says it went 1 m straight on.
    const ParticleScan second = scan_at(Rigid2d(1.0, 0.03, 0.0));
    const Rigid2d motion(1.0, 0.0, 0.0);
    const bool improved = proposal == ParticleProposal::kImprovedProposal;
    // The motion model also samples the heading (sigma 6 degrees here), which tilts the kept
    // axis; its translation noise alone would be 0.11 m.
    const double x_tolerance = improved ? 0.002 : 0.03;
    double mean_y = 0.0;
    const int draws = 20;
    for (int i = 0; i < draws; ++i) {
      std::mt19937_64 rng = ParticleRandomStream(1, 1, static_cast<size_t>(i));
      const ProposalDraw draw = DrawPose(Rigid2d(), motion, motion, second, map, options, &rng);
      EXPECT_NEAR(draw.pose.x(), 1.0, x_tolerance) << "draw " << i;
      EXPECT_EQ(draw.used_scan_match, improved);
      mean_y += draw.pose.y() / draws;
    }
    if (improved) {
      EXPECT_NEAR(mean_y, 0.03, 0.01);
    }
  }
}

// In the room, the robot truly moved to (1, 0.5, 0.1); the motion says (1.12, 0.41, 0.12). With
// wheel-odometry noise and the lattice on the match (GMapping), the draws land at the true pose:
// the match finds it and the broad prior does not hold it back. With scan-matched noise and the
// lattice on the prediction, they stay near the prediction: the scan can pull them at most a
// lattice step (2.5 cm, 0.01 rad) towards the truth, and the tight prior holds them there.
TEST(ParticleFilterTest, LatticeOnThePredictionStaysNearItWithATightMotionModel) {
  ParticleFilterOptions options;
  SharedTileGrid map(options.grid, 1);
  const ParticleScan first = ScanAt(Rigid2d());
  map.InsertRays(Eigen::Vector2d::Zero(), first.ray_ends, first.ray_hits);
  const Rigid2d truth(1.0, 0.5, 0.1);
  const Rigid2d motion(1.12, 0.41, 0.12);
  const ParticleScan second = ScanAt(truth);
  for (bool on_prediction : {false, true}) {
    options.centre_on_prediction = on_prediction;
    options.motion_noise = on_prediction ? MotionNoise::ScanMatched() : MotionNoise::WheelOdometry();
    for (int i = 0; i < 10; ++i) {
      std::mt19937_64 rng = ParticleRandomStream(1, 1, static_cast<size_t>(i));
      const ProposalDraw draw = DrawPose(Rigid2d(), motion, motion, second, map, options, &rng);
      ASSERT_TRUE(draw.used_scan_match);
      const Rigid2d from_truth = truth.inverse() * draw.pose;
      const Rigid2d from_prediction = motion.inverse() * draw.pose;
      if (on_prediction) {
        EXPECT_LT(from_prediction.translation().norm(), 0.045) << "draw " << i;
        EXPECT_LT(std::abs(from_prediction.rotation()), 0.015) << "draw " << i;
        EXPECT_GT(from_truth.translation().norm(), 0.1) << "draw " << i;
      } else {
        EXPECT_LT(from_truth.translation().norm(), 0.03) << "draw " << i;
        EXPECT_LT(std::abs(from_truth.rotation()), 0.01) << "draw " << i;
      }
    }
  }
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
  options.motion_noise.srr = 0.5;  // wide motion noise: the scan separates good particles from bad ones
  options.motion_noise.str = 0.5;
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

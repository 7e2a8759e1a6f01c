#include <cmath>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot_agent/localization/free_space.h"
#include "robot_agent/localization/landmark_model.h"
#include "robot_agent/localization/likelihood_field_model.h"
#include "robot_agent/localization/motion_model.h"
#include "robot_agent/localization/particle.h"
#include "robot_agent/localization/resampling.h"
#include "tests/localization/localization_world.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(MotionModelTest, NoiseFreeSampleFollowsOdometry) {
  OdometryMotionModelOptions options;
  options.alpha1 = options.alpha2 = options.alpha3 = options.alpha4 = 0.0;
  const Rigid2d delta(0.3, 0.1, 0.2);
  const OdometrySampler sampler(delta, options);
  std::mt19937 rng(1);
  const Rigid2d start(1.0, 2.0, 0.5);
  EXPECT_THAT(sampler.Sample(start, rng), testing::IsNearPose(start * delta, 1e-9, 1e-9));
}

TEST(MotionModelTest, ReverseDrivingIsNotTwoHalfTurns) {
  const OdometryParts parts = DecomposeOdometry(Rigid2d(-0.2, 0.0, 0.0));
  EXPECT_NEAR(parts.trans, -0.2, 1e-12);
  EXPECT_NEAR(parts.rot1, 0.0, 1e-12);
  EXPECT_NEAR(parts.rot2, 0.0, 1e-12);
}

TEST(MotionModelTest, SpreadGrowsWithDistanceAndMeanStaysOnTrack) {
  OdometryMotionModelOptions options;
  std::mt19937 rng(3);
  const Rigid2d delta(1.0, 0.0, 0.0);
  const OdometrySampler sampler(delta, options);
  double sum = 0.0, sum_sq = 0.0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const double x = sampler.Sample(Rigid2d(), rng).x();
    sum += x;
    sum_sq += x * x;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 1.0, 0.02);
  const double std = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(std, std::sqrt(options.alpha3), 0.03);
}

TEST(ResamplingTest, LowVarianceSelectIsProportional) {
  std::vector<Particle> particles(4);
  particles[0].weight = 0.1;
  particles[1].weight = 0.0;
  particles[2].weight = 0.6;
  particles[3].weight = 0.3;
  std::mt19937 rng(1);
  std::vector<int> indices;
  LowVarianceSelect(particles, 10, rng, &indices);
  ASSERT_EQ(indices.size(), 10u);
  std::vector<int> counts(4, 0);
  for (const int i : indices) ++counts[static_cast<size_t>(i)];
  EXPECT_EQ(counts[0], 1);
  EXPECT_EQ(counts[1], 0);
  EXPECT_EQ(counts[2], 6);
  EXPECT_EQ(counts[3], 3);
}

TEST(ResamplingTest, KldCountGrowsWithBins) {
  KldOptions options;
  EXPECT_EQ(KldSampleCount(1, options), options.min_particles);
  const int few = KldSampleCount(20, options);
  const int many = KldSampleCount(200, options);
  EXPECT_GT(many, few);
  EXPECT_EQ(KldSampleCount(1000000, options), options.max_particles);
  // Fox 2003: k = 100 bins, epsilon = 0.05, delta = 0.01 needs about 1,350 samples.
  options.min_particles = 1;
  EXPECT_NEAR(KldSampleCount(100, options), 1347, 5);
}

TEST(ResamplingTest, CountsDistinctBins) {
  std::vector<Particle> particles{{Rigid2d(0.1, 0.1, 0.0), 1}, {Rigid2d(0.2, 0.2, 0.01), 1},
                                  {Rigid2d(3.0, 0.1, 0.0), 1}, {Rigid2d(0.1, 0.1, 2.0), 1}};
  std::vector<int64_t> scratch;
  EXPECT_EQ(CountOccupiedBins(particles, {0, 1, 2, 3}, KldOptions(), &scratch), 3);
  EXPECT_EQ(CountOccupiedBins(particles, {0, 0, 1}, KldOptions(), &scratch), 1);
}

TEST(EstimateTest, ConvergedOnlyWhenTight) {
  std::vector<Particle> tight{{Rigid2d(1.0, 1.0, 3.1), 0.5}, {Rigid2d(1.1, 1.0, -3.1), 0.5}};
  const PoseEstimate estimate = ComputeEstimate(tight, ConvergenceOptions());
  EXPECT_TRUE(estimate.converged);
  EXPECT_THAT(estimate.robot_in_map, testing::IsNearPose(Rigid2d(1.05, 1.0, M_PI), 1e-9, 1e-6));
  std::vector<Particle> split{{Rigid2d(1.0, 1.0, 0.0), 0.5}, {Rigid2d(4.0, 1.0, 0.0), 0.5}};
  EXPECT_FALSE(ComputeEstimate(split, ConvergenceOptions()).converged);
  std::vector<Particle> headings{{Rigid2d(1.0, 1.0, 0.0), 0.5}, {Rigid2d(1.0, 1.0, 1.5), 0.5}};
  EXPECT_FALSE(ComputeEstimate(headings, ConvergenceOptions()).converged);
}

TEST(LandmarkModelTest, TruePoseScoresHighest) {
  const LandmarkMap landmarks{{1, {2.0, 0.0}}, {2, {0.0, 3.0}}};
  const Rigid2d truth(0.5, 0.5, 0.3);
  std::vector<LandmarkObservation> observations;
  for (const auto& [id, position] : landmarks) {
    const Eigen::Vector2d d = truth.inverse() * position;
    observations.push_back({id, d.norm(), std::atan2(d.y(), d.x())});
  }
  observations.push_back({99, 1.0, 0.0});  // unknown id: ignored
  std::vector<Particle> particles{{truth, 1}, {Rigid2d(0.7, 0.5, 0.3), 1},
                                  {Rigid2d(0.5, 0.5, 0.5), 1}};
  std::vector<double> ll;
  EXPECT_EQ(LandmarkLogLikelihoods(observations, landmarks, LandmarkModelOptions(), particles, &ll),
            2);
  ASSERT_EQ(ll.size(), 3u);
  EXPECT_GT(ll[0], ll[1]);
  EXPECT_GT(ll[0], ll[2]);
}

TEST(LikelihoodFieldModelTest, TruePoseScoresHighest) {
  const testing::Room room = testing::AsymmetricRoom();
  const LikelihoodField field(room.grid, LikelihoodFieldOptions());
  LikelihoodFieldModel model(field, LikelihoodFieldModelOptions());
  const Rigid2d truth(2.0, 2.2, 0.4);
  const LaserScan scan = testing::SimulateScan(room.walls, truth);
  std::vector<Particle> particles{{truth, 1}, {Rigid2d(2.2, 2.2, 0.4), 1},
                                  {Rigid2d(2.0, 2.2, 0.5), 1}};
  std::vector<double> ll;
  EXPECT_EQ(model.ComputeLogLikelihoods(scan, particles, &ll), 60);
  EXPECT_GT(ll[0], ll[1] + 5.0);
  EXPECT_GT(ll[0], ll[2] + 5.0);
  // A scan without returns says nothing.
  LaserScan empty = scan;
  for (float& r : empty.ranges) r = LaserScan::kNoReturn;
  EXPECT_EQ(model.ComputeLogLikelihoods(empty, particles, &ll), 0);
  EXPECT_EQ(ll[0], 0.0);
}

TEST(FreeSpaceTest, BoxSamplesStayInside) {
  const FreeSpace space = FreeSpace::FromBox({-1, -2}, {3, 4});
  EXPECT_DOUBLE_EQ(space.area(), 24.0);
  std::mt19937 rng(2);
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(space.IsFree(space.SamplePoint(rng)));
  EXPECT_FALSE(space.IsFree({3.5, 0}));
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/localization/particle_clusters.h"

#include <cmath>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// `count` equal-weight particles on a small ring around `center`.
void AddBlob(const Rigid2d& center, int count, double weight, std::vector<Particle>* particles) {
  for (int i = 0; i < count; ++i) {
    const double a = 2.0 * M_PI * i / count;
    particles->push_back(Particle{
        Rigid2d(center.translation() + 0.05 * Eigen::Vector2d(std::cos(a), std::sin(a)),
                center.rotation() + 0.01 * std::sin(a)),
        weight / count});
  }
}

TEST(ParticleClustersTest, SeparatesDistantBlobsHeaviestFirst) {
  std::vector<Particle> particles;
  AddBlob(Rigid2d(1.0, 1.0, 0.0), 40, 0.3, &particles);
  AddBlob(Rigid2d(9.0, 1.0, 0.0), 40, 0.7, &particles);
  const std::vector<ParticleCluster> clusters = ClusterParticles(particles, ClusterOptions());
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_NEAR(clusters[0].weight, 0.7, 1e-9);
  EXPECT_NEAR(clusters[1].weight, 0.3, 1e-9);
  EXPECT_EQ(clusters[0].members.size(), 40u);
  EXPECT_GE(clusters[0].members.front(), 40);  // the second blob's particles
}

TEST(ParticleClustersTest, HeadingsWrapAroundPi) {
  std::vector<Particle> particles{{Rigid2d(1.0, 1.0, M_PI - 0.01), 1.0},
                                  {Rigid2d(1.0, 1.0, -M_PI + 0.01), 1.0}};
  EXPECT_EQ(ClusterParticles(particles, ClusterOptions()).size(), 1u);
  EXPECT_TRUE(ClusterParticles({}, ClusterOptions()).empty());
}

TEST(ParticleClustersTest, SmallFarModeDoesNotBlockConvergence) {
  const Rigid2d truth(2.0, 3.0, 0.5);
  std::vector<Particle> particles;
  AddBlob(truth, 100, 0.96, &particles);
  AddBlob(Rigid2d(20.0, 3.0, -2.0), 10, 0.04, &particles);  // a look-alike pose far away
  // The mean over all particles sits between the modes and is not converged ...
  EXPECT_FALSE(ComputeEstimate(particles, ConvergenceOptions()).converged);
  // ... the heaviest cluster is the truth.
  const PoseEstimate estimate = ComputeClusteredEstimate(particles, ConvergenceOptions());
  EXPECT_TRUE(estimate.converged);
  EXPECT_THAT(estimate.robot_in_map, testing::IsNearPose(truth, 0.01, 0.01));
  EXPECT_NEAR(estimate.cluster_weight, 0.96, 1e-9);
  EXPECT_EQ(estimate.cluster_count, 2);
}

TEST(ParticleClustersTest, TwoComparableModesAreNotConverged) {
  std::vector<Particle> particles;
  AddBlob(Rigid2d(2.0, 3.0, 0.5), 100, 0.6, &particles);
  AddBlob(Rigid2d(20.0, 3.0, 0.5), 100, 0.4, &particles);
  const PoseEstimate estimate = ComputeClusteredEstimate(particles, ConvergenceOptions());
  EXPECT_FALSE(estimate.converged);
  EXPECT_THAT(estimate.robot_in_map, testing::IsNearPose(Rigid2d(2.0, 3.0, 0.5), 0.01, 0.01));
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/localization/mcl.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "shared/core/likelihood_field.h"
#include "tests/localization/localization_world.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::AsymmetricRoom;
using testing::IsNearPose;
using testing::MassNear;
using testing::Room;
using testing::SimulateScan;
using testing::SymmetricRoom;
using testing::SymmetricTwin;

MclOptions SmallFilterOptions(uint32_t seed) {
  MclOptions options;
  options.kld.max_particles = 3000;
  options.kld.min_particles = 500;
  options.seed = seed;
  return options;
}

// Drives the robot around a circle (0.08 m and 0.1 rad per step), feeding exact odometry and
// exact scans to the filter; returns the final true pose.
Rigid2d Drive(const Room& room, Rigid2d robot_in_map, int steps, Mcl* mcl,
              LikelihoodFieldModel* model) {
  const Rigid2d step(0.08, 0.0, 0.1);
  for (int i = 0; i < steps; ++i) {
    robot_in_map = robot_in_map * step;
    mcl->Predict(step);
    mcl->UpdateLaser(SimulateScan(room.walls, robot_in_map), *model);
  }
  return robot_in_map;
}

TEST(MclTest, GlobalLocalizationConvergesInAsymmetricRoom) {
  const Room room = AsymmetricRoom();
  const LikelihoodField field(room.grid, LikelihoodFieldOptions());
  LikelihoodFieldModel model(field, LikelihoodFieldModelOptions());
  Mcl mcl(FreeSpace::FromGrid(room.grid), SmallFilterOptions(7));
  mcl.InitializeUniform();
  EXPECT_FALSE(mcl.Estimate().converged);
  const Rigid2d truth = Drive(room, Rigid2d(2.0, 2.2, 0.0), 60, &mcl, &model);
  const PoseEstimate estimate = mcl.Estimate();
  EXPECT_TRUE(estimate.converged);
  EXPECT_THAT(estimate.robot_in_map, IsNearPose(truth, 0.15, 0.08));
  // KLD sampling shrinks the set once the belief is focused.
  EXPECT_LT(estimate.particle_count, 1500);
}

TEST(MclTest, SymmetricRoomStaysMultiModal) {
  const Room room = SymmetricRoom();
  const LikelihoodField field(room.grid, LikelihoodFieldOptions());
  LikelihoodFieldModel model(field, LikelihoodFieldModelOptions());
  Mcl mcl(FreeSpace::FromGrid(room.grid), SmallFilterOptions(2));
  mcl.InitializeUniform();
  const Rigid2d truth = Drive(room, Rigid2d(1.5, 0.8, 0.0), 20, &mcl, &model);
  const double at_truth = MassNear(mcl.particles(), truth);
  const double at_twin = MassNear(mcl.particles(), SymmetricTwin(room, truth));
  EXPECT_GT(at_truth, 0.1);
  EXPECT_GT(at_twin, 0.1);
  EXPECT_GT(at_truth + at_twin, 0.9);
  EXPECT_FALSE(mcl.Estimate().converged);
}

TEST(MclTest, RecoversFromKidnapping) {
  const Room room = AsymmetricRoom();
  const LikelihoodField field(room.grid, LikelihoodFieldOptions());
  LikelihoodFieldModel model(field, LikelihoodFieldModelOptions());
  Mcl mcl(FreeSpace::FromGrid(room.grid), SmallFilterOptions(11));
  const Rigid2d start(2.0, 2.2, 0.0);
  mcl.InitializeGaussian(start, Eigen::Vector3d(0.01, 0.01, 0.005).asDiagonal());
  Rigid2d truth = Drive(room, start, 30, &mcl, &model);
  ASSERT_THAT(mcl.Estimate().robot_in_map, IsNearPose(truth, 0.15, 0.08));
  // Carry the robot to the other side of the room without telling the filter.
  const Rigid2d kidnapped(6.5, 1.0, 0.0);
  truth = Drive(room, kidnapped, 150, &mcl, &model);
  const PoseEstimate estimate = mcl.Estimate();
  EXPECT_TRUE(estimate.converged);
  EXPECT_THAT(estimate.robot_in_map, IsNearPose(truth, 0.15, 0.08));
}

TEST(MclTest, SameSeedGivesSameParticles) {
  const Room room = AsymmetricRoom();
  const LikelihoodField field(room.grid, LikelihoodFieldOptions());
  LikelihoodFieldModel model(field, LikelihoodFieldModelOptions());
  Mcl a(FreeSpace::FromGrid(room.grid), SmallFilterOptions(5));
  Mcl b(FreeSpace::FromGrid(room.grid), SmallFilterOptions(5));
  Mcl c(FreeSpace::FromGrid(room.grid), SmallFilterOptions(6));
  a.InitializeUniform(1000);
  b.InitializeUniform(1000);
  c.InitializeUniform(1000);
  Drive(room, Rigid2d(2.0, 2.2, 0.0), 10, &a, &model);
  Drive(room, Rigid2d(2.0, 2.2, 0.0), 10, &b, &model);
  Drive(room, Rigid2d(2.0, 2.2, 0.0), 10, &c, &model);
  ASSERT_EQ(a.particles().size(), b.particles().size());
  for (size_t i = 0; i < a.particles().size(); ++i) {
    EXPECT_EQ(a.particles()[i].robot_in_map.x(), b.particles()[i].robot_in_map.x());
    EXPECT_EQ(a.particles()[i].robot_in_map.rotation(), b.particles()[i].robot_in_map.rotation());
    EXPECT_EQ(a.particles()[i].weight, b.particles()[i].weight);
  }
  EXPECT_NE(a.particles().front().robot_in_map.x(), c.particles().front().robot_in_map.x());
}

TEST(MclTest, ParticlesStayInFreeSpaceAfterUniformInit) {
  const Room room = AsymmetricRoom();
  Mcl mcl(FreeSpace::FromGrid(room.grid), SmallFilterOptions(1));
  mcl.InitializeUniform(500);
  for (const Particle& p : mcl.particles()) {
    EXPECT_TRUE(mcl.free_space().IsFree(p.robot_in_map.translation()));
    EXPECT_FALSE(p.robot_in_map.x() > 5.5 && p.robot_in_map.x() < 6.5 && p.robot_in_map.y() > 3.0 &&
                 p.robot_in_map.y() < 4.0);
  }
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/localization/collaborative_update.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "shared/core/likelihood_field.h"
#include "tests/localization/localization_world.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

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

RobotDetection DetectionOf(const Rigid2d& observed_in_map, const Rigid2d& observer_in_map) {
  RobotDetection detection;
  detection.observer_id = "b";
  detection.observed_id = "a";
  detection.position_in_observer = observer_in_map.inverse() * observed_in_map.translation();
  detection.covariance = Eigen::Matrix2d::Identity() * 0.05 * 0.05;
  return detection;
}

// Robot a is lost in the symmetric room with a two-mode belief; robot b stands still at the
// other end, looking at it.
class CollaborativeTest : public ::testing::Test {
 protected:
  CollaborativeTest()
      : room_(SymmetricRoom()),
        field_(room_.grid, LikelihoodFieldOptions()),
        model_(field_, LikelihoodFieldModelOptions()),
        a_(FreeSpace::FromGrid(room_.grid), SmallFilterOptions(2)),
        b_(FreeSpace::FromGrid(room_.grid), SmallFilterOptions(22)) {
    a_.InitializeUniform();
    a_truth_ = Drive(Rigid2d(1.5, 0.8, 0.0), 20);
  }

  Rigid2d Drive(Rigid2d robot_in_map, int steps) {
    const Rigid2d step(0.08, 0.0, 0.1);
    for (int i = 0; i < steps; ++i) {
      robot_in_map = robot_in_map * step;
      a_.Predict(step);
      a_.UpdateLaser(SimulateScan(room_.walls, robot_in_map), model_);
    }
    return robot_in_map;
  }

  Room room_;
  LikelihoodField field_;
  LikelihoodFieldModel model_;
  Mcl a_;
  Mcl b_;
  Rigid2d a_truth_;
  const Rigid2d b_truth_{4.8, 1.5, M_PI};
};

TEST_F(CollaborativeTest, DetectionFromFocusedObserverPicksTheRightMode) {
  const Rigid2d twin = SymmetricTwin(room_, a_truth_);
  ASSERT_GT(MassNear(a_.particles(), a_truth_), 0.1);
  ASSERT_GT(MassNear(a_.particles(), twin), 0.1);
  b_.InitializeGaussian(b_truth_, Eigen::Vector3d(0.0025, 0.0025, 0.0004).asDiagonal());
  const auto density = SummarizeDetection(b_.particles(), DetectionOf(a_truth_, b_truth_),
                                          DetectionSummaryOptions(), b_.rng());
  ASSERT_TRUE(density.has_value());
  ASSERT_TRUE(ApplyPoseDensity(*density, DensityUpdateOptions(), &a_));
  EXPECT_GT(MassNear(a_.particles(), a_truth_), 0.9);
  EXPECT_LT(MassNear(a_.particles(), twin), 0.02);
  // The laser then tracks the chosen mode. A few per cent stay at the twin: the detection
  // model allows for a 5 % chance of a misidentified robot, and the laser cannot tell the twins
  // apart.
  const Rigid2d truth = Drive(a_truth_, 10);
  EXPECT_GT(MassNear(a_.particles(), truth), 0.95);
  EXPECT_THAT(a_.Estimate().robot_in_map, IsNearPose(truth, 0.15, 0.08));
}

TEST_F(CollaborativeTest, UnfocusedObserverIsNotHeard) {
  b_.InitializeUniform(2000);
  EXPECT_FALSE(SummarizeDetection(b_.particles(), DetectionOf(a_truth_, b_truth_),
                                  DetectionSummaryOptions(), b_.rng())
                   .has_value());
}

TEST_F(CollaborativeTest, UnfocusedObserverDoesNotCollapseTheBelief) {
  // Even with the focus guard switched off, a vague observer's density is too broad to pick a
  // mode: both twins keep their weight.
  b_.InitializeUniform(2000);
  DetectionSummaryOptions no_guard;
  no_guard.max_observer_position_std = 1e9;
  no_guard.max_observer_heading_std = 1e9;
  const auto density = SummarizeDetection(b_.particles(), DetectionOf(a_truth_, b_truth_),
                                          no_guard, b_.rng());
  ASSERT_TRUE(density.has_value());
  ApplyPoseDensity(*density, DensityUpdateOptions(), &a_);
  EXPECT_GT(MassNear(a_.particles(), a_truth_), 0.1);
  EXPECT_GT(MassNear(a_.particles(), SymmetricTwin(room_, a_truth_)), 0.1);
}

TEST_F(CollaborativeTest, FocusedRobotMostlyKeepsItsBeliefAgainstAContradiction) {
  // a is sure of itself; b reports it in the middle of the room.
  a_.InitializeGaussian(a_truth_, Eigen::Vector3d(0.0025, 0.0025, 0.0004).asDiagonal());
  b_.InitializeGaussian(b_truth_, Eigen::Vector3d(0.0025, 0.0025, 0.0004).asDiagonal());
  const Rigid2d reported(3.0, 1.5, 0.0);
  const auto density = SummarizeDetection(b_.particles(), DetectionOf(reported, b_truth_),
                                          DetectionSummaryOptions(), b_.rng());
  ASSERT_TRUE(density.has_value());
  EXPECT_TRUE(ApplyPoseDensity(*density, DensityUpdateOptions(), &a_));
  EXPECT_GT(MassNear(a_.particles(), a_truth_), 0.7);
  // A few particles wait at the reported place, in case a's belief was the wrong one.
  EXPECT_GT(MassNear(a_.particles(), reported, 0.5, 4.0), 0.01);
}

TEST_F(CollaborativeTest, LostRobotSettledOnTheTwinIsMovedByADetection) {
  // a started uniform and converged on the wrong twin (what particle depletion does in a
  // look-alike corridor): a detection outweighs such a belief and the robot stays "globally
  // localizing" until a detection agrees with its belief.
  const Rigid2d twin = SymmetricTwin(room_, a_truth_);
  a_.InitializeGaussian(twin, Eigen::Vector3d(0.0025, 0.0025, 0.0004).asDiagonal());
  a_.set_globally_localizing(true);
  b_.InitializeGaussian(b_truth_, Eigen::Vector3d(0.0025, 0.0025, 0.0004).asDiagonal());
  const auto density = SummarizeDetection(b_.particles(), DetectionOf(a_truth_, b_truth_),
                                          DetectionSummaryOptions(), b_.rng());
  ASSERT_TRUE(density.has_value());
  ASSERT_TRUE(ApplyPoseDensity(*density, DensityUpdateOptions(), &a_));
  EXPECT_GT(MassNear(a_.particles(), a_truth_, 0.5, 4.0), 0.8);
  EXPECT_TRUE(a_.globally_localizing());
  // The laser picks the heading; the next detection then agrees with the belief.
  const Rigid2d truth = Drive(a_truth_, 10);
  ASSERT_TRUE(ApplyPoseDensity(*SummarizeDetection(b_.particles(), DetectionOf(truth, b_truth_),
                                                   DetectionSummaryOptions(), b_.rng()),
                               DensityUpdateOptions(), &a_));
  EXPECT_FALSE(a_.globally_localizing());
  EXPECT_GT(MassNear(a_.particles(), truth), 0.8);
}

TEST(PoseDensityTest, SummaryIsCentredOnTheDetectedRobot) {
  std::vector<Particle> observer;
  for (int i = 0; i < 100; ++i) {
    observer.push_back(Particle{Rigid2d(1.0, 2.0, M_PI / 2), 0.01});
  }
  RobotDetection detection;
  detection.position_in_observer = Eigen::Vector2d(2.0, 0.0);  // 2 m ahead = +y in the map
  detection.covariance = Eigen::Matrix2d::Identity() * 0.01;
  std::mt19937 rng(1);
  const auto density = SummarizeDetection(observer, detection, DetectionSummaryOptions(), rng);
  ASSERT_TRUE(density.has_value());
  EXPECT_FALSE(density->has_heading);
  EXPECT_LE(density->kernels.size(), 50u);
  const double at_peak = density->Evaluate(Rigid2d(1.0, 4.0, 0.3));
  EXPECT_GT(at_peak, density->Evaluate(Rigid2d(1.2, 4.0, 0.3)));
  EXPECT_NEAR(at_peak, density->Evaluate(Rigid2d(1.0, 4.0, -2.0)), 1e-12);  // heading unknown
  // Peak of a 2D Gaussian with sigma ~0.1 m, times 1 / (2 pi) for the heading.
  EXPECT_NEAR(at_peak, 1.0 / (2 * M_PI * 0.01 * 2 * M_PI), 0.2 * at_peak);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i = 0; i < 2000; ++i) mean += density->Sample(rng).translation() / 2000.0;
  EXPECT_NEAR(mean.x(), 1.0, 0.02);
  EXPECT_NEAR(mean.y(), 4.0, 0.02);
}

TEST(PoseDensityTest, RejectsMalformedDetections) {
  std::vector<Particle> observer{Particle{Rigid2d(), 1.0}};
  std::mt19937 rng(1);
  RobotDetection detection;
  detection.covariance = Eigen::Matrix2d::Zero();
  EXPECT_FALSE(SummarizeDetection(observer, detection, DetectionSummaryOptions(), rng));
  detection.covariance = Eigen::Matrix2d::Identity();
  detection.position_in_observer.x() = NAN;
  EXPECT_FALSE(SummarizeDetection(observer, detection, DetectionSummaryOptions(), rng));
  EXPECT_FALSE(SummarizeDetection({}, RobotDetection(), DetectionSummaryOptions(), rng));
}

TEST(DetectionGateTest, RateLimitsEachPair) {
  DetectionGate gate(2.0);
  EXPECT_TRUE(gate.Allow("b", "a", 10.0));
  EXPECT_FALSE(gate.Allow("b", "a", 11.0));
  EXPECT_TRUE(gate.Allow("a", "b", 11.0));  // the other direction is another pair
  EXPECT_TRUE(gate.Allow("b", "a", 12.5));
}

TEST(DetectionGateTest, ARobotStillGloballyLocalizingTakesDetectionsSooner) {
  DetectionGate gate(2.0, 0.5);
  EXPECT_TRUE(gate.Allow("b", "a", 10.0, /*observed_lost=*/true));
  EXPECT_FALSE(gate.Allow("b", "a", 10.3, true));
  EXPECT_TRUE(gate.Allow("b", "a", 10.5, true));
  EXPECT_FALSE(gate.Allow("b", "a", 11.0, false));  // confirmed: the pair's interval again
  EXPECT_TRUE(gate.Allow("b", "a", 12.5, false));
}

}  // namespace
}  // namespace fleetmap

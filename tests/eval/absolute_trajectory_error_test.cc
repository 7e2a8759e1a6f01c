#include "shared/eval/absolute_trajectory_error.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shared/eval/rigid_alignment.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

Trajectory Spiral(int count) {
  Trajectory trajectory;
  for (int i = 0; i < count; ++i) {
    const double a = 0.1 * i;
    trajectory.push_back({static_cast<double>(i),
                          Rigid2d((1 + a) * std::cos(a), (1 + a) * std::sin(a), a + M_PI / 2)});
  }
  return trajectory;
}

Trajectory Transformed(const Trajectory& trajectory, const Rigid2d& transform) {
  Trajectory out;
  for (const StampedPose& p : trajectory) out.push_back({p.timestamp, transform * p.pose});
  return out;
}

TEST(AlignPoints2dTest, RecoversAKnownRigidTransform) {
  const Rigid2d transform(3.0, -2.0, 0.7);
  std::vector<Eigen::Vector2d> source;
  std::vector<Eigen::Vector2d> target;
  for (const StampedPose& p : Spiral(20)) {
    source.push_back(p.pose.translation());
    target.push_back(transform * p.pose.translation());
  }
  const auto found = AlignPoints2d(source, target);
  ASSERT_TRUE(found.has_value());
  EXPECT_THAT(*found, IsNearPose(transform, 1e-9, 1e-9));
}

TEST(AlignPoints2dTest, DegenerateInputsHaveNoAnswer) {
  EXPECT_FALSE(AlignPoints2d({{1, 1}}, {{2, 2}}).has_value());
  EXPECT_FALSE(AlignPoints2d({{1, 1}, {1, 1}}, {{2, 2}, {3, 3}}).has_value());
  EXPECT_FALSE(AlignPoints2d({{1, 1}, {2, 1}}, {{2, 2}}).has_value());
}

TEST(AteTest, KnownRigidOffsetWithoutAlignmentGivesItsDistance) {
  const Trajectory truth = Spiral(50);
  // A pure translation of (0.3, 0.4): every pose is exactly 0.5 m off.
  const Trajectory estimate = Transformed(truth, Rigid2d(0.3, 0.4, 0.0));
  const auto result = EvaluateAte(estimate, truth);
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->matched, 50);
  EXPECT_NEAR(result->rmse_translation, 0.5, 1e-12);
  EXPECT_NEAR(result->translation.mean, 0.5, 1e-12);
  EXPECT_NEAR(result->rmse_rotation_deg, 0.0, 1e-9);
}

TEST(AteTest, AlignmentRemovesARigidOffset) {
  const Trajectory truth = Spiral(50);
  const Rigid2d offset(5.0, -1.0, 1.2);
  const Trajectory estimate = Transformed(truth, offset);
  AteOptions options;
  options.align = true;
  const auto result = EvaluateAte(estimate, truth, options);
  ASSERT_TRUE(result.has_value());
  EXPECT_NEAR(result->rmse_translation, 0.0, 1e-9);
  EXPECT_NEAR(result->rmse_rotation_deg, 0.0, 1e-7);
  EXPECT_THAT(result->ground_truth_from_estimate, IsNearPose(offset.inverse(), 1e-9, 1e-9));
  // Without alignment the error is large.
  EXPECT_GT(EvaluateAte(estimate, truth)->rmse_translation, 1.0);
}

TEST(AteTest, AssociatesByNearestTimeWithinTolerance) {
  const Trajectory truth = {{0.0, Rigid2d(0, 0, 0)}, {1.0, Rigid2d(1, 0, 0)}};
  const Trajectory estimate = {{0.004, Rigid2d(0, 0, 0)},  // pairs with t=0
                               {0.996, Rigid2d(1, 1, 0)},  // pairs with t=1, 1 m off
                               {0.5, Rigid2d(0, 0, 0)}};   // nothing within 10 ms
  const auto result = EvaluateAte(estimate, truth);
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->matched, 2);
  EXPECT_EQ(result->unmatched, 1);
  EXPECT_NEAR(result->rmse_translation, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(result->translation.max, 1.0, 1e-12);
}

TEST(AteTest, NoMatchesGiveNoResult) {
  EXPECT_FALSE(EvaluateAte({{5.0, Rigid2d()}}, {{0.0, Rigid2d()}}).has_value());
  EXPECT_FALSE(EvaluateAte({}, {}).has_value());
}

}  // namespace
}  // namespace fleetmap

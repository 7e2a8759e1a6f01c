#include "shared/eval/relations_metric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "shared/eval/relations_file.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

// A square path: poses every second along a 10 m x 10 m square.
Trajectory SquarePath() {
  Trajectory trajectory;
  double t = 100.0;
  Rigid2d pose(0.0, 0.0, 0.0);
  for (int side = 0; side < 4; ++side) {
    for (int step = 0; step < 10; ++step) {
      trajectory.push_back({t, pose});
      t += 1.0;
      pose = pose * Rigid2d(1.0, 0.0, 0.0);
    }
    pose = pose * Rigid2d(0.0, 0.0, M_PI / 2);
  }
  return trajectory;
}

// Relations taken from the true trajectory itself: every pair 5 steps apart.
std::vector<Relation> TrueRelations(const Trajectory& truth) {
  std::vector<Relation> relations;
  for (size_t i = 0; i + 5 < truth.size(); ++i) {
    relations.push_back(
        {truth[i].timestamp, truth[i + 5].timestamp, truth[i].pose.inverse() * truth[i + 5].pose});
  }
  return relations;
}

TEST(RelationsMetricTest, ErrorIsZeroOnTheTrueTrajectory) {
  const Trajectory truth = SquarePath();
  const RelationsResult result = EvaluateRelations(truth, TrueRelations(truth));
  EXPECT_EQ(result.used, 35);
  EXPECT_EQ(result.skipped, 0);
  EXPECT_NEAR(result.translation.mean, 0.0, 1e-12);
  EXPECT_NEAR(result.rotation_deg.mean, 0.0, 1e-10);
}

TEST(RelationsMetricTest, KnownTranslationAndRotationErrors) {
  // Two relations; the estimate is off by a known amount in each.
  const Trajectory estimate = {
      {1.0, Rigid2d(0, 0, 0)}, {2.0, Rigid2d(1.0, 0.0, 0.0)}, {3.0, Rigid2d(2.0, 0.0, 0.1)}};
  // Relation 1->2 expects (1.3, 0, 0): estimate (1, 0, 0), error translation -0.3.
  // Relation 2->3 expects (1, 0, -0.1) rotation: estimate (1, 0, 0.1), error rotation 0.2 rad.
  const std::vector<Relation> relations = {{1.0, 2.0, Rigid2d(1.3, 0.0, 0.0)},
                                           {2.0, 3.0, Rigid2d(1.0, 0.0, -0.1)}};
  const RelationsResult result = EvaluateRelations(estimate, relations);
  ASSERT_EQ(result.used, 2);
  // Errors: e1 = (-0.3, 0, 0); e2 = (1,0,0.1) * (1,0,-0.1)^-1.
  const Rigid2d e2 = Rigid2d(1, 0, 0.1) * Rigid2d(1, 0, -0.1).inverse();
  EXPECT_THAT(RelationError(estimate[1].pose, estimate[2].pose, relations[1].expected),
              IsNearPose(e2, 1e-12, 1e-12));
  const double t1 = 0.3;
  const double t2 = e2.translation().norm();
  const double r2 = 0.2 * 180.0 / M_PI;
  EXPECT_NEAR(result.translation.mean, (t1 + t2) / 2, 1e-9);
  EXPECT_NEAR(result.translation.std, std::abs(t1 - t2) / 2, 1e-9);
  EXPECT_NEAR(result.squared_translation.mean, (t1 * t1 + t2 * t2) / 2, 1e-9);
  EXPECT_NEAR(result.rotation_deg.mean, r2 / 2, 1e-9);
  EXPECT_NEAR(result.rotation_deg.std, r2 / 2, 1e-9);
  EXPECT_NEAR(result.squared_rotation_deg.mean, r2 * r2 / 2, 1e-9);
  EXPECT_NEAR(result.rotation_deg.max, r2, 1e-9);
}

TEST(RelationsMetricTest, ConstantHeadingBiasGivesKnownError) {
  // The estimate turns 1 degree too much at each corner of the square: relations that span a
  // corner see exactly 1 degree of rotation error, the others none.
  const Trajectory truth = SquarePath();
  Trajectory estimate;
  Rigid2d pose;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {
      const Rigid2d step = truth[i - 1].pose.inverse() * truth[i].pose;
      const double extra = std::abs(step.rotation()) > 0.1 ? M_PI / 180 : 0.0;
      pose = pose * Rigid2d(step.translation(), step.rotation() + extra);
    }
    estimate.push_back({truth[i].timestamp, pose});
  }
  const std::vector<Relation> relations = TrueRelations(truth);
  const RelationsResult result = EvaluateRelations(estimate, relations);
  int spanning = 0;
  for (const Relation& r : relations) {
    const int i = static_cast<int>(r.from_timestamp - 100.0);
    const int corner_a = 10 * (i / 10 + 1);  // first corner step after i
    spanning += (i + 5 >= corner_a) ? 1 : 0;
  }
  EXPECT_NEAR(result.rotation_deg.mean, static_cast<double>(spanning) / result.used, 1e-9);
}

TEST(RelationsMetricTest, MissingTimestampsAreSkippedNotMatchedApproximately) {
  const Trajectory estimate = {{10.000000, Rigid2d()}, {11.000000, Rigid2d(1, 0, 0)}};
  const std::vector<Relation> relations = {
      {10.0, 11.0, Rigid2d(1, 0, 0)},
      {10.0, 11.00001, Rigid2d(1, 0, 0)},    // 10 us off: no exact match
      {10.0000004, 11.0, Rigid2d(1, 0, 0)},  // within 1 us: matches
      {9.0, 11.0, Rigid2d(1, 0, 0)}};
  const RelationsResult result = EvaluateRelations(estimate, relations);
  EXPECT_EQ(result.used, 2);
  EXPECT_EQ(result.skipped, 2);
}

TEST(RelationsMetricTest, EmptyInputsGiveZeroUsed) {
  const RelationsResult result = EvaluateRelations({}, {{1.0, 2.0, Rigid2d()}});
  EXPECT_EQ(result.used, 0);
  EXPECT_EQ(result.skipped, 1);
  EXPECT_EQ(result.translation.mean, 0.0);
}

class RelationsFileTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) {
    const std::string path = dir_.path() + "/r.relations";
    std::ofstream(path) << text;
    return path;
  }
  const testing::ScopedTempDir dir_{"fleetmap-relations"};
};

TEST_F(RelationsFileTest, ReadsBenchmarkLines) {
  std::vector<Relation> relations;
  std::string error;
  ASSERT_TRUE(ReadRelations(
      Write("# c\n976052905.167303 976052911.885496 -0.056990 -0.128430 0.000000 0.000000 "
            "0.000000 -1.682210\n\n"),
      &relations, &error))
      << error;
  ASSERT_EQ(relations.size(), 1u);
  EXPECT_DOUBLE_EQ(relations[0].from_timestamp, 976052905.167303);
  EXPECT_DOUBLE_EQ(relations[0].to_timestamp, 976052911.885496);
  EXPECT_THAT(relations[0].expected,
              IsNearPose(Rigid2d(-0.05699, -0.12843, -1.68221), 1e-12, 1e-12));
}

TEST_F(RelationsFileTest, BadLinesNameFileAndLine) {
  std::vector<Relation> relations;
  std::string error;
  EXPECT_FALSE(ReadRelations(Write("1 2 3 4 5 6 7 8\n1 2 3\n"), &relations, &error));
  EXPECT_NE(error.find(":2: expected 8 values"), std::string::npos) << error;
  EXPECT_FALSE(ReadRelations(Write("1 2 3 4 5 6 7 nan\n"), &relations, &error));
  EXPECT_NE(error.find(":1: value 8"), std::string::npos) << error;
  EXPECT_FALSE(ReadRelations(dir_.path() + "/missing", &relations, &error));
  EXPECT_NE(error.find("missing"), std::string::npos) << error;
}

}  // namespace
}  // namespace fleetmap

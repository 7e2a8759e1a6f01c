#include "map_server/ctl/ctl_evaluate.h"

#include <gtest/gtest.h>

#include <fstream>

#include "map_server/ctl/localization_error.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(CtlEvaluateTest, PerfectPlacementsHaveZeroError) {
  const std::map<std::string, Rigid2d> truth = {{"a", Rigid2d(2, 3, 0.5)},
                                                {"b", Rigid2d(-4, 1, -2.0)}};
  // The server's global frame is arbitrary: here it is a's local frame.
  const Rigid2d global_in_world = truth.at("a");
  std::map<std::string, Rigid2d> placements;
  for (const auto& [name, start] : truth) placements[name] = global_in_world.inverse() * start;
  const MergeEvaluation e = EvaluatePlacements(placements, truth);
  ASSERT_EQ(e.pairs.size(), 1u);
  EXPECT_EQ(e.pairs[0].reference, "a");
  EXPECT_NEAR(e.pairs[0].translation_error, 0.0, 1e-9);
  EXPECT_NEAR(e.pairs[0].rotation_error, 0.0, 1e-9);
  EXPECT_TRUE(e.unplaced.empty());
}

TEST(CtlEvaluateTest, KnownOffsetIsMeasuredAndUnplacedListed) {
  const std::map<std::string, Rigid2d> truth = {
      {"a", Rigid2d(0, 0, 0)}, {"b", Rigid2d(5, 0, M_PI / 2)}, {"c", Rigid2d(1, 1, 0)}};
  std::map<std::string, Rigid2d> placements = {{"a", Rigid2d(10, 10, 1.0)}};
  // b placed 3 cm and 0.01 rad off (expressed in a's frame).
  placements["b"] = placements["a"] * Rigid2d(5.03, 0.0, M_PI / 2 + 0.01);
  const MergeEvaluation e = EvaluatePlacements(placements, truth);
  ASSERT_EQ(e.pairs.size(), 1u);
  EXPECT_NEAR(e.pairs[0].translation_error, 0.03, 1e-9);
  EXPECT_NEAR(e.pairs[0].rotation_error, 0.01, 1e-9);
  ASSERT_EQ(e.unplaced.size(), 1u);
  EXPECT_EQ(e.unplaced[0], "c");
}

TEST(CtlEvaluateTest, BadGroundTruthFilesAreErrors) {
  const testing::ScopedTempDir temp("fleetmap-evaluate");
  const std::string& dir = temp.path();
  std::map<std::string, Rigid2d> starts;
  std::string error;
  EXPECT_FALSE(ReadStartPoses(dir + "/missing.yaml", &starts, &error));
  std::ofstream(dir + "/bad.yaml") << "robots:\n  - name: a\n";
  EXPECT_FALSE(ReadStartPoses(dir + "/bad.yaml", &starts, &error));
  EXPECT_NE(error.find("start"), std::string::npos);
  std::ofstream(dir + "/nan.yaml")
      << "robots:\n  - name: a\n    start: {x: .nan, y: 0, theta: 0}\n";
  EXPECT_FALSE(ReadStartPoses(dir + "/nan.yaml", &starts, &error));
  std::ofstream(dir + "/ok.yaml") << "robots:\n  - name: a\n    start: {x: 1, y: 2, theta: 0.5}\n";
  ASSERT_TRUE(ReadStartPoses(dir + "/ok.yaml", &starts, &error)) << error;
  EXPECT_NEAR(starts.at("a").y(), 2.0, 1e-12);
}

// A localizing robot's poses against its true ones: matched by time, offsets measured exactly.
TEST(CtlEvaluateTest, LocalizationErrorMatchesPosesByTimeAndMeasuresTheOffsets) {
  Trajectory truth, estimated;
  for (int i = 0; i < 10; ++i) truth.push_back({0.06 * i, Rigid2d(0.1 * i, 0.0, 0.0)});
  // Three poses at true times (0.1 m, 0.3 m and 0.2 m / 0.1 rad off), one between ticks.
  estimated.push_back({0.0, Rigid2d(0.0, 0.1, 0.0)});
  estimated.push_back({0.12 + 0.001, Rigid2d(0.2, -0.3, 0.0)});
  estimated.push_back({0.09, Rigid2d(5.0, 5.0, 0.0)});
  estimated.push_back({0.54, Rigid2d(0.9, 0.2, 0.1)});
  const LocalizationError error = ScoreTrajectory(estimated, truth);
  EXPECT_EQ(error.matched, 3);
  EXPECT_NEAR(error.mean_position, 0.2, 1e-9);
  EXPECT_NEAR(error.max_position, 0.3, 1e-9);
  EXPECT_NEAR(error.final_position, 0.2, 1e-9);
  EXPECT_NEAR(error.max_heading, 0.1, 1e-9);
  EXPECT_NEAR(error.final_heading, 0.1, 1e-9);
  EXPECT_EQ(ScoreTrajectory(estimated, Trajectory()).matched, 0);
}

}  // namespace
}  // namespace fleetmap

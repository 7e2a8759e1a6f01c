#include "map_server/ctl/ctl_evaluate.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

TEST(CtlEvaluateTest, MapAccuracyCountsCellsNearWalls) {
  OccupancyGridOptions options;
  options.resolution = 0.05;
  OccupancyGrid world(options, Eigen::Vector2d(0, 0), 100, 100);
  for (int i = 0; i < 100; ++i) world.SetLogOdds(CellIndex(i, 50), 4.0f);  // wall at y = 2.525
  OccupancyGrid global(options, Eigen::Vector2d(0, 0), 100, 100);
  for (int i = 0; i < 90; ++i) global.SetLogOdds(CellIndex(i, 50), 4.0f);  // on the wall
  for (int i = 0; i < 10; ++i) global.SetLogOdds(CellIndex(i, 80), 4.0f);  // 1.5 m off
  long occupied = 0;
  EXPECT_NEAR(MapAccuracy(global, world, Rigid2d(), 0.05, &occupied), 0.9, 1e-9);
  EXPECT_EQ(occupied, 100);
  // Shifting the global frame by 1 m in y puts the "on the wall" cells off it.
  EXPECT_NEAR(MapAccuracy(global, world, Rigid2d(0, 1.0, 0), 0.05, &occupied), 0.0, 1e-9);
  // Shifted by 0.12 m, the best rigid placement nearby puts them back on it.
  double best_fit = 0.0;
  EXPECT_NEAR(MapAccuracy(global, world, Rigid2d(0, 0.12, 0), 0.05, &occupied, &best_fit), 0.0,
              1e-9);
  EXPECT_NEAR(best_fit, 0.9, 1e-9);
}

TEST(CtlEvaluateTest, BadGroundTruthFilesAreErrors) {
  const std::string dir = testing::MakeTempDir("fleetmap-evaluate");
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
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fleetmap

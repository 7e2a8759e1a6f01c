#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot_agent/localization/tool/error_plot.h"
#include "robot_agent/localization/tool/mrclam_reader.h"
#include "robot_agent/localization/tool/mrclam_replay.h"
#include "shared/io/map_file.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

constexpr char kMrclam[] = "utias-mrclam/resampled_50Hz_full_groundtruth";

TEST(MrclamReaderTest, ReadsTheResampledSet) {
  FLEETMAP_REQUIRE_DATA(barcodes, std::string(kMrclam) + "/Barcodes.dat");
  const std::string dir = std::filesystem::path(barcodes).parent_path().string();
  MrclamDataset dataset;
  std::string error;
  ASSERT_TRUE(ReadMrclam(dir, 5, &dataset, &error)) << error;
  EXPECT_EQ(dataset.landmarks.size(), 15u);
  ASSERT_EQ(dataset.robots.size(), 5u);
  EXPECT_EQ(dataset.robots[0].barcode, 5);
  EXPECT_EQ(dataset.robots[4].barcode, 23);
  EXPECT_EQ(dataset.robot_by_barcode.at(41), 2);
  EXPECT_NEAR(dataset.landmarks.at(18).x(), 0.19173646, 1e-9);  // barcode-keyed
  EXPECT_EQ(dataset.robots[0].measurements.size(), 8753u);

  // Two minutes of the log with the collaborative update: every robot stays localized.
  LocalizationReplayOptions options;
  options.collaborative = true;
  // 300 particles lose a robot now and then in landmark-only MCL (robot4, seed 1: 0.92 m after
  // a split at 74 s); 500 kept every robot below 0.5 m over seeds 1-6.
  options.particles = 500;
  options.max_time = 120.0;
  const ReplayResult result = ReplayMrclam(dataset, options, nullptr);
  ASSERT_EQ(result.robots.size(), 5u);
  for (const RobotReplayResult& robot : result.robots) {
    EXPECT_LT(robot.mean_position_error, 0.6) << robot.name;
    EXPECT_GT(robot.position_error.points.size(), 100u);
  }
}

TEST(MrclamReaderTest, MissingAndMalformedFilesGiveClearErrors) {
  MrclamDataset dataset;
  std::string error;
  EXPECT_FALSE(ReadMrclam("/nonexistent", 5, &dataset, &error));
  EXPECT_THAT(error, ::testing::HasSubstr("cannot open /nonexistent/Barcodes.dat"));
  const testing::ScopedTempDir temp("mrclam");
  const std::string& dir = temp.path();
  std::ofstream(dir + "/Barcodes.dat") << "1\t5\n";
  std::ofstream(dir + "/Landmark_Groundtruth.dat") << "18 0.1 oops\n";
  EXPECT_FALSE(ReadMrclam(dir, 1, &dataset, &error));
  EXPECT_THAT(error, ::testing::HasSubstr("Landmark_Groundtruth.dat:1"));
}

TEST(ErrorPlotTest, DrawsColouredLines) {
  const testing::ScopedTempDir temp("plot");
  const std::string& dir = temp.path();
  ErrorSeries series{"r1", {{0.0, 0.0}, {10.0, 1.0}}};
  std::string error;
  ASSERT_TRUE(WriteErrorPlot(dir + "/plot.png", {series}, ErrorPlotOptions(), &error)) << error;
  EXPECT_GT(std::filesystem::file_size(dir + "/plot.png"), 100u);
  EXPECT_DOUBLE_EQ(TickStep(1900, 10), 200);
  EXPECT_DOUBLE_EQ(TickStep(1.0, 8), 0.2);
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/slam/log_runner.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "robot_agent/slam/scan_matching_slam.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// A FLASER line with `ranges` and the robot at `pose` (laser at the same pose).
std::string Flaser(const std::vector<double>& ranges, const Rigid2d& pose, double time) {
  std::ostringstream line;
  line.precision(10);
  line << "FLASER " << ranges.size();
  for (double r : ranges) line << " " << r;
  for (int i = 0; i < 2; ++i) line << " " << pose.x() << " " << pose.y() << " " << pose.rotation();
  line << " " << time << " host " << time << "\n";
  return line.str();
}

std::string WriteLog(const testing::ScopedTempDir& dir, const std::string& name,
                     const std::string& content) {
  const std::string path = dir.path() + "/" + name;
  std::ofstream(path) << content;
  return path;
}

std::vector<double> RoomRanges(const Rigid2d& pose) {
  const LaserScan scan = testing::SimulateScan(
      testing::BoxWorld(Eigen::Vector2d(-3.0, -2.0), Eigen::Vector2d(4.0, 2.5)), pose, 180,
      static_cast<float>(-M_PI / 2), static_cast<float>(M_PI / 180), 40.0f);
  std::vector<double> ranges;
  for (float r : scan.ranges) ranges.push_back(std::isfinite(r) ? r : 81.83);
  return ranges;
}

TEST(LoadSlamLogTest, ReadsScansInTimeOrderWithTheirOdometry) {
  const testing::ScopedTempDir dir("slam_log");
  std::string content = "PARAM robot_frontlaser_offset 0.0 nohost 0\n";
  content += Flaser(RoomRanges(Rigid2d()), Rigid2d(), 10.0);
  content += Flaser(RoomRanges(Rigid2d(0.2, 0.0, 0.0)), Rigid2d(0.2, 0.0, 0.0), 10.3);
  // Logged late: 0.1 s older than the line before it. Re-sorted, with a warning.
  content += Flaser(RoomRanges(Rigid2d(0.1, 0.0, 0.0)), Rigid2d(0.1, 0.0, 0.0), 10.2);
  SlamLog log;
  std::string error;
  ASSERT_TRUE(LoadSlamLog(WriteLog(dir, "ok.clf", content), SlamLogOptions(), &log, &error))
      << error;
  ASSERT_EQ(log.scans.size(), 3u);
  EXPECT_DOUBLE_EQ(log.scans[1].timestamp, 10.2);
  EXPECT_DOUBLE_EQ(log.odometry[1].pose.x(), 0.1);
  EXPECT_EQ(log.odometry_source, "laser lines");
  EXPECT_EQ(log.warnings.size(), 1u);

  ScanMatchingSlam slam;
  SlamRunResult result;
  std::vector<size_t> reported;
  auto progress = [&](size_t done, size_t total) {
    EXPECT_EQ(total, 3u);
    reported.push_back(done);
  };
  ASSERT_TRUE(RunSlam(log, &slam, &result, &error, progress)) << error;
  ASSERT_EQ(result.trajectory.size(), 3u);
  EXPECT_THAT(result.trajectory[2].pose, testing::IsNearPose(Rigid2d(0.2, 0.0, 0.0), 0.02, 0.01));
  EXPECT_FALSE(result.submaps.empty());
  // Now and then, then once with every scan in (before the backend's final work), only once.
  EXPECT_EQ(reported, (std::vector<size_t>{1, 2, 3}));
}

TEST(LoadSlamLogTest, BadLogsFailWithAClearMessage) {
  const testing::ScopedTempDir dir("slam_log");
  SlamLog log;
  std::string error;
  EXPECT_FALSE(LoadSlamLog("/nonexistent/log.clf", SlamLogOptions(), &log, &error));
  EXPECT_FALSE(error.empty());

  EXPECT_FALSE(LoadSlamLog(WriteLog(dir, "empty.clf", ""), SlamLogOptions(), &log, &error));
  EXPECT_NE(error.find("no laser scans"), std::string::npos) << error;

  const std::string only_odometry =
      "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 0.1 0 0 0 0 0 1.1 host 1.1\n";
  EXPECT_FALSE(
      LoadSlamLog(WriteLog(dir, "odom.clf", only_odometry), SlamLogOptions(), &log, &error));
  EXPECT_NE(error.find("no laser scans"), std::string::npos) << error;

  std::string no_returns;
  for (int i = 0; i < 5; ++i) no_returns += Flaser(std::vector<double>(180, 81.83), Rigid2d(0.1 * i, 0, 0), i);
  EXPECT_FALSE(
      LoadSlamLog(WriteLog(dir, "noreturn.clf", no_returns), SlamLogOptions(), &log, &error));
  EXPECT_NE(error.find("no returns"), std::string::npos) << error;

  std::string backwards = Flaser(RoomRanges(Rigid2d()), Rigid2d(), 100.0);
  backwards += Flaser(RoomRanges(Rigid2d()), Rigid2d(), 50.0);
  EXPECT_FALSE(
      LoadSlamLog(WriteLog(dir, "backwards.clf", backwards), SlamLogOptions(), &log, &error));
  EXPECT_NE(error.find("time goes backwards"), std::string::npos) << error;
  SlamLogOptions skip;
  skip.skip_out_of_order = true;
  ASSERT_TRUE(LoadSlamLog(WriteLog(dir, "backwards.clf", backwards), skip, &log, &error)) << error;
  EXPECT_EQ(log.scans.size(), 1u);
}

TEST(LoadSlamLogTest, ConstantOdometryIsAcceptedWithAWarning) {
  const testing::ScopedTempDir dir("slam_log");
  std::string content;
  for (int i = 0; i < 3; ++i) content += Flaser(RoomRanges(Rigid2d(0.05 * i, 0.0, 0.0)), Rigid2d(), i);
  SlamLog log;
  std::string error;
  ASSERT_TRUE(LoadSlamLog(WriteLog(dir, "noodom.clf", content), SlamLogOptions(), &log, &error))
      << error;
  EXPECT_EQ(log.odometry_source, "none");
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("odometry never changes"), std::string::npos);
  ScanMatchingSlam slam;
  SlamRunResult result;
  ASSERT_TRUE(RunSlam(log, &slam, &result, &error)) << error;
  EXPECT_THAT(result.trajectory.back().pose, testing::IsNearPose(Rigid2d(0.1, 0.0, 0.0), 0.03, 0.02));
}

}  // namespace
}  // namespace fleetmap

// Runs fleetmap-log and fleetmap-eval as processes (found under FLEETMAP_BINARY_DIR) on a small
// log generated here, and checks their outputs and exit codes.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "shared/io/carmen_writer.h"
#include "shared/io/map_file.h"
#include "shared/io/trajectory_file.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using ::testing::HasSubstr;

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// The tools' folder in the build tree this test belongs to.
std::string ToolDir() { return testing::TestBuildDir() + "/shared/tools"; }

class ToolsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* tool : {"fleetmap-log", "fleetmap-eval"}) {
      const std::string path = ToolDir() + "/" + tool;
      if (!std::filesystem::exists(path)) GTEST_FAIL() << "tool not built: " << path;
    }
  }

  RunResult Run(const std::string& tool, const std::string& args) {
    const std::string out = dir_.path() + "/stdout.txt";
    const std::string err = dir_.path() + "/stderr.txt";
    const std::string command = ToolDir() + "/" + tool + " " + args + " > " + out + " 2> " + err;
    const int status = std::system(command.c_str());
    RunResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = testing::ReadWholeFile(out);
    result.err = testing::ReadWholeFile(err);
    return result;
  }

  // A robot driving a loop inside a 10 m x 6 m room; returns the true trajectory.
  Trajectory WriteRoomLog(const std::string& path, int scans) {
    const testing::SegmentWorld world =
        testing::BoxWorld(Eigen::Vector2d(-5, -3), Eigen::Vector2d(5, 3));
    CarmenWriter writer(path, "sim");
    EXPECT_TRUE(writer.ok());
    writer.WriteParam("robot_frontlaser_offset", "0.0", 1000.0);
    Trajectory truth;
    for (int i = 0; i < scans; ++i) {
      const double a = 2 * M_PI * i / scans;
      const double t = 1000.0 + 0.1 * i;
      const Rigid2d pose(2.5 * std::cos(a), 1.5 * std::sin(a), a + M_PI / 2);
      OdometryRecord odometry;
      odometry.timestamp = t - 0.01;
      odometry.robot_pose = pose;
      writer.WriteOdometry(odometry);
      LaserRecord laser;
      laser.scan = testing::SimulateScan(world, pose, 181);
      laser.scan.timestamp = t;
      laser.robot_pose = pose;
      laser.laser_pose = pose;
      writer.WriteLaser(laser);
      truth.push_back({t, pose});
    }
    EXPECT_TRUE(writer.Close());
    return truth;
  }

  const testing::ScopedTempDir dir_{"fleetmap-tools"};
};

TEST_F(ToolsTest, HelpForEveryToolAndSubcommand) {
  for (const std::string args :
       {"fleetmap-log --help", "fleetmap-log info --help", "fleetmap-log map --help",
        "fleetmap-log trajectory --help", "fleetmap-eval --help", "fleetmap-eval relations --help",
        "fleetmap-eval ate --help"}) {
    const std::string tool = args.substr(0, args.find(' '));
    const RunResult r = Run(tool, args.substr(args.find(' ') + 1));
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    EXPECT_THAT(r.out, HasSubstr("Usage")) << args;
  }
}

TEST_F(ToolsTest, MissingArgumentsAndFilesExitNonZero) {
  EXPECT_NE(Run("fleetmap-log", "").exit_code, 0);
  EXPECT_NE(Run("fleetmap-log", "info").exit_code, 0);
  EXPECT_NE(Run("fleetmap-log", "info " + dir_.path() + "/missing.clf").exit_code, 0);
  EXPECT_NE(Run("fleetmap-eval", "relations --trajectory " + dir_.path() + "/missing").exit_code,
            0);
  EXPECT_NE(Run("fleetmap-eval", "bogus").exit_code, 0);
}

TEST_F(ToolsTest, InfoReportsWhatTheLogHolds) {
  const std::string log = dir_.path() + "/room.clf";
  WriteRoomLog(log, 40);
  const RunResult r = Run("fleetmap-log", "info " + log);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("laser scans: 40"));
  EXPECT_THAT(r.out, HasSubstr("181 beams: 40 scans"));
  EXPECT_THAT(r.out, HasSubstr("odometry records: 40"));
  EXPECT_THAT(r.out, HasSubstr("FLASER=40"));
  EXPECT_THAT(r.out, HasSubstr("robot_frontlaser_offset = 0.0"));
  EXPECT_THAT(r.out, HasSubstr("skipped bad lines: 0"));
}

TEST_F(ToolsTest, MapWritesAMapOfTheRoomAndTheTrajectory) {
  const std::string log = dir_.path() + "/room.clf";
  const Trajectory truth = WriteRoomLog(log, 40);
  const std::string out = dir_.path() + "/out";
  const RunResult r = Run("fleetmap-log", "map " + log + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* file : {"map.pgm", "map.yaml", "map.png", "trajectory.txt"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  }
  OccupancyGrid grid;
  std::string error;
  ASSERT_TRUE(ReadMap(out + "/map.yaml", &grid, &error)) << error;
  // Walls occupied, the room's centre free.
  EXPECT_GT(grid.Probability(grid.CellAt(Eigen::Vector2d(4.99, 0.5))), 0.5f);
  EXPECT_GT(grid.Probability(grid.CellAt(Eigen::Vector2d(0.5, -2.99))), 0.5f);
  EXPECT_LT(grid.Probability(grid.CellAt(Eigen::Vector2d(0.3, 0.2))), 0.5f);
  Trajectory trajectory;
  ASSERT_TRUE(ReadTrajectory(out + "/trajectory.txt", &trajectory, &error)) << error;
  ASSERT_EQ(trajectory.size(), truth.size());
  EXPECT_NEAR(trajectory[7].timestamp, truth[7].timestamp, 1e-6);
}

TEST_F(ToolsTest, TrajectoryThenRelationsAndAte) {
  const std::string log = dir_.path() + "/room.clf";
  const Trajectory truth = WriteRoomLog(log, 30);
  const std::string trajectory = dir_.path() + "/odometry.txt";
  RunResult r = Run("fleetmap-log", "trajectory " + log + " --out " + trajectory);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // Relations from the true poses, one of them 0.5 m off: mean error 0.5 / count.
  std::ofstream relations(dir_.path() + "/room.relations");
  relations.precision(6);
  relations << std::fixed;
  for (size_t i = 0; i + 1 < truth.size(); ++i) {
    const Rigid2d relative = truth[i].pose.inverse() * truth[i + 1].pose;
    const double extra = i == 3 ? 0.5 : 0.0;
    relations << truth[i].timestamp << " " << truth[i + 1].timestamp << " " << relative.x() + extra
              << " " << relative.y() << " 0 0 0 " << relative.rotation() << "\n";
  }
  relations << "5.000000 6.000000 1 0 0 0 0 0\n";  // not in the log: skipped
  relations.close();
  r = Run("fleetmap-eval", "relations --trajectory " + trajectory + " --relations " + dir_.path() +
                               "/room.relations");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("relations: 29 used, 1 skipped (of 30)"));
  r = Run("fleetmap-eval",
          "relations --json -t " + trajectory + " -r " + dir_.path() + "/room.relations");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("\"used\": 29"));
  const size_t at = r.out.find("\"translation_m\": {\"mean\": ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double mean = std::stod(r.out.substr(at + 27));
  EXPECT_NEAR(mean, 0.5 / 29, 1e-4);

  // ATE against a ground truth shifted by (0.3, 0.4): 0.5 m; with --align about 0.
  Trajectory shifted;
  for (const StampedPose& p : truth)
    shifted.push_back({p.timestamp, Rigid2d(0.3, 0.4, 0) * p.pose});
  std::string error;
  ASSERT_TRUE(WriteTrajectory(dir_.path() + "/gt.txt", shifted, &error)) << error;
  r = Run("fleetmap-eval",
          "ate --trajectory " + trajectory + " --ground-truth " + dir_.path() + "/gt.txt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("ATE translation RMSE [m]   0.5000"));
  r = Run("fleetmap-eval",
          "ate --align --trajectory " + trajectory + " --ground-truth " + dir_.path() + "/gt.txt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("ATE translation RMSE [m]   0.0000"));
}

TEST_F(ToolsTest, MalformedLogExitsNonZeroNamingTheLine) {
  const std::string log = dir_.path() + "/bad.clf";
  std::ofstream(log) << "ODOM 0 0 0 0 0 0 1.0 h 0\nFLASER 3 1 2 0 0 0 0 0 0 2.0 h 0\n";
  for (const char* command : {"info ", "map --out out "}) {
    const RunResult r = Run("fleetmap-log", command + log);
    EXPECT_NE(r.exit_code, 0) << command;
    EXPECT_THAT(r.err, HasSubstr(log + ":2: FLASER")) << command;
  }
  // With --skip-bad-lines, info succeeds and counts the line.
  const RunResult r = Run("fleetmap-log", "info --skip-bad-lines " + log);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("skipped bad lines: 1"));
}

TEST_F(ToolsTest, IntelRawOdometryRelationsUseAll2984) {
  FLEETMAP_REQUIRE_DATA(log, "intel-lab/intel.clf.bz2");
  FLEETMAP_REQUIRE_DATA(relations, "intel-lab/intel.relations");
  const std::string trajectory = dir_.path() + "/intel-odometry.txt";
  RunResult r = Run("fleetmap-log", "trajectory " + log + " --out " + trajectory);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("13631 poses"));
  r = Run("fleetmap-eval", "relations --trajectory " + trajectory + " --relations " + relations);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("relations: 2984 used, 0 skipped (of 2984)"));
}

TEST_F(ToolsTest, BadTrajectoryFileExitsNonZero) {
  std::ofstream(dir_.path() + "/t.txt") << "1 2 3\n";
  std::ofstream(dir_.path() + "/r.relations") << "1 2 0 0 0 0 0 0\n";
  const RunResult r = Run(
      "fleetmap-eval", "relations -t " + dir_.path() + "/t.txt -r " + dir_.path() + "/r.relations");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("t.txt:1: expected 4 values"));
}

}  // namespace
}  // namespace fleetmap

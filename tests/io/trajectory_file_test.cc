#include "shared/io/trajectory_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

class TrajectoryFileTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) {
    const std::string path = dir_.path() + "/t.txt";
    std::ofstream(path) << text;
    return path;
  }
  const testing::ScopedTempDir dir_{"fleetmap-trajectory-file"};
};

TEST_F(TrajectoryFileTest, RoundTripKeepsMicrosecondTimestamps) {
  const Trajectory trajectory = {{976052857.337530, Rigid2d(1.25, -3.5, 0.75)},
                                 {976052857.348896, Rigid2d(-100.123456, 0.0, -3.0)},
                                 {976052857.348896, Rigid2d(0.0, 1e-6, 3.1)}};
  const std::string path = dir_.path() + "/round.txt";
  std::string error;
  ASSERT_TRUE(WriteTrajectory(path, trajectory, &error)) << error;
  Trajectory read;
  ASSERT_TRUE(ReadTrajectory(path, &read, &error)) << error;
  ASSERT_EQ(read.size(), trajectory.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_NEAR(read[i].timestamp, trajectory[i].timestamp, 5e-7);
    EXPECT_THAT(read[i].pose, IsNearPose(trajectory[i].pose, 1e-6, 1e-8));
  }
}

TEST_F(TrajectoryFileTest, CommentsAndBlankLinesAreSkipped) {
  Trajectory read;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(Write("# header\n\n1.0 2 3 0.5\r\n  2.0\t4 5 -0.5\n"), &read, &error))
      << error;
  ASSERT_EQ(read.size(), 2u);
  EXPECT_THAT(read[1].pose, IsNearPose(Rigid2d(4, 5, -0.5), 1e-12, 1e-12));
}

TEST_F(TrajectoryFileTest, BadLinesNameFileAndLine) {
  const struct {
    const char* text;
    const char* fragment;
  } cases[] = {
      {"1 2 3 4\n1 2 3\n", ":2: expected 4 values"},
      {"1 2 3 4 5\n", ":1: expected 4 values"},
      {"1 2 x 4\n", ":1: value 3 'x' is not a number"},
      {"1 2 nan 4\n", ":1: value 3 is not finite"},
      {"1 inf 3 4\n", ":1: value 2 is not finite"},
  };
  for (const auto& c : cases) {
    Trajectory read;
    std::string error;
    EXPECT_FALSE(ReadTrajectory(Write(c.text), &read, &error)) << c.text;
    EXPECT_NE(error.find(c.fragment), std::string::npos) << error;
  }
}

TEST_F(TrajectoryFileTest, OutOfOrderTimestampsKeepFileOrder) {
  // Raw CARMEN logs (intel) have ipc_timestamps that go backwards now and then.
  Trajectory read;
  std::string error;
  ASSERT_TRUE(ReadTrajectory(Write("5 0 0 0\n4 1 0 0\n6 2 0 0\n"), &read, &error)) << error;
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(read[1].timestamp, 4.0);
  EXPECT_EQ(read[1].pose.x(), 1.0);
}

TEST_F(TrajectoryFileTest, MissingFileAndUnwritablePath) {
  Trajectory read;
  std::string error;
  EXPECT_FALSE(ReadTrajectory(dir_.path() + "/missing.txt", &read, &error));
  EXPECT_NE(error.find("missing.txt"), std::string::npos);
  EXPECT_FALSE(WriteTrajectory(dir_.path() + "/no/dir/t.txt", Trajectory(), &error));
  EXPECT_NE(error.find("cannot write"), std::string::npos);
}

}  // namespace
}  // namespace fleetmap

#include "robot_agent/detection/tools/sim_dataset.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// A minimal simulator output folder in the formats of robot_agent/sim/output_writer.cc.
void WriteFakeRun(const std::string& dir) {
  std::ofstream(dir + "/manifest.yaml")
      << "robot_body: {radius: 0.200, body_height: 0.350, marker_radius: 0.200, "
         "marker_z_min: 0.350, marker_z_max: 0.650}\n"
         "laser: {rate: 10.000, beams: 181, fov_deg: 180.000, max_range: 8.000, "
         "range_noise: 0.0100}\n"
         "robots:\n"
         "  - name: robot1\n    index: 0\n    log: robot1.clf\n    ground_truth: robot1.gt.txt\n"
         "    camera_index: robot1_camera/index.txt\n"
         "  - name: robot2\n    index: 1\n    log: robot2.clf\n    ground_truth: robot2.gt.txt\n"
         "visibility: visibility.txt\n";
  std::filesystem::create_directories(dir + "/robot1_camera");
  std::ofstream(dir + "/robot1_camera/index.txt")
      << "# timestamp file width height fx fy cx cy mount_x mount_y mount_z mount_yaw\n"
         "0.200000 frame_000001.png 640 480 554.256258 554.256258 320.000 240.000 0.1000 "
         "0.0000 0.5500 0.000000\n";
  std::ofstream(dir + "/visibility.txt")
      << "# timestamp observer observed range bearing rel_x rel_y rel_theta in_camera_fov "
         "occluded visible image_u image_width\n"
         "0.200000 robot1 robot2 3.0000 0.00000 3.0000 0.0000 3.14159 yes no yes 320.0 38.0\n";
}

TEST(SimDatasetTest, ReadsManifestIndexAndVisibility) {
  const testing::ScopedTempDir temp("sim_dataset");
  const std::string& dir = temp.path();
  WriteFakeRun(dir);
  SimDataset data;
  std::string error;
  ASSERT_TRUE(ReadSimDataset(dir, &data, &error)) << error;
  ASSERT_EQ(data.robots.size(), 2u);
  ASSERT_EQ(data.robots[0].frames.size(), 1u);
  EXPECT_TRUE(data.robots[1].frames.empty());
  const CameraModel& camera = data.robots[0].frames[0].camera;
  EXPECT_DOUBLE_EQ(camera.cx, 319.5);  // pixel edges -> pixel centres
  EXPECT_DOUBLE_EQ(camera.mount_height, 0.55);
  EXPECT_DOUBLE_EQ(camera.camera_in_robot.x(), 0.1);
  EXPECT_DOUBLE_EQ(data.geometry.marker_radius, 0.2);
  ASSERT_EQ(data.visibility.size(), 1u);
  EXPECT_TRUE(data.visibility[0].visible);
  EXPECT_EQ(data.visibility[0].observed, "robot2");
}

TEST(SimDatasetTest, BrokenFilesGiveMessages) {
  const testing::ScopedTempDir temp("sim_dataset");
  const std::string& dir = temp.path();
  WriteFakeRun(dir);
  SimDataset data;
  std::string error;
  std::ofstream(dir + "/visibility.txt") << "0.2 robot1 robot2 3.0\n";
  EXPECT_FALSE(ReadSimDataset(dir, &data, &error));
  EXPECT_NE(error.find("visibility.txt:1"), std::string::npos) << error;
  std::ofstream(dir + "/manifest.yaml") << "robots: 3\n";
  EXPECT_FALSE(ReadSimDataset(dir, &data, &error));
  EXPECT_FALSE(ReadSimDataset(dir + "/nowhere", &data, &error));
  std::vector<LaserScan> scans;
  EXPECT_FALSE(ReadLaserScans(dir + "/robot1.clf", &scans, &error));
}

TEST(SimDatasetTest, NearestScanAndInterpolatedPose) {
  std::vector<LaserScan> scans(3);
  scans[0].timestamp = 1.0;
  scans[1].timestamp = 1.1;
  scans[2].timestamp = 1.2;
  EXPECT_EQ(NearestScan(scans, 1.12, 0.05), &scans[1]);
  EXPECT_EQ(NearestScan(scans, 1.5, 0.05), nullptr);
  const Trajectory trajectory = {{0.0, Rigid2d(0.0, 0.0, 0.0)}, {1.0, Rigid2d(2.0, 0.0, 0.0)}};
  Rigid2d pose;
  ASSERT_TRUE(PoseAt(trajectory, 0.25, &pose));
  EXPECT_NEAR(pose.x(), 0.5, 1e-12);
  EXPECT_FALSE(PoseAt(trajectory, 2.0, &pose));
}

}  // namespace
}  // namespace fleetmap

#include "shared/io/carmen_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "shared/io/carmen_reader.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

class CarmenWriterTest : public ::testing::Test {
 protected:
  std::vector<CarmenRecord> ReadBack(const std::string& path) {
    std::string error;
    auto reader = CarmenReader::Open(path, CarmenReaderOptions(), &error);
    EXPECT_NE(reader, nullptr) << error;
    std::vector<CarmenRecord> records;
    if (!reader) return records;
    CarmenRecord record;
    while (reader->Next(&record)) records.push_back(record);
    EXPECT_EQ(reader->error(), "");
    return records;
  }
  const testing::ScopedTempDir dir_{"fleetmap-carmen-writer"};
};

LaserRecord MakeLaser(double timestamp, const Rigid2d& robot_pose, int beams, float angle_min,
                      float increment, float range_max, const Rigid2d& mount) {
  std::vector<float> ranges;
  for (int i = 0; i < beams; ++i) {
    // Some returns, some beyond range_max (no-return), one NaN (no-return).
    ranges.push_back(i % 7 == 3 ? range_max + 1.0f : 0.5f + 0.0137f * static_cast<float>(i));
  }
  ranges[1] = std::nanf("");
  LaserRecord laser;
  laser.scan = MakeLaserScan(timestamp, angle_min, increment, 0.0f, range_max, ranges, mount);
  laser.robot_pose = robot_pose;
  laser.laser_pose = robot_pose * mount;
  return laser;
}

void ExpectSameLaser(const LaserRecord& actual, const LaserRecord& expected) {
  EXPECT_NEAR(actual.scan.timestamp, expected.scan.timestamp, 1e-6);
  EXPECT_THAT(actual.robot_pose, IsNearPose(expected.robot_pose, 2e-6, 2e-6));
  EXPECT_THAT(actual.scan.sensor_in_robot, IsNearPose(expected.scan.sensor_in_robot, 5e-6, 5e-6));
  EXPECT_NEAR(actual.scan.angle_min, expected.scan.angle_min, 1e-6);
  EXPECT_NEAR(actual.scan.angle_increment, expected.scan.angle_increment, 1e-6);
  ASSERT_EQ(actual.scan.size(), expected.scan.size());
  for (int i = 0; i < expected.scan.size(); ++i) {
    EXPECT_EQ(actual.scan.IsReturn(i), expected.scan.IsReturn(i)) << i;
    if (expected.scan.IsReturn(i)) {
      EXPECT_EQ(actual.scan.ranges[i], expected.scan.ranges[i]) << i;
    }
  }
}

TEST_F(CarmenWriterTest, FlaserOdometryAndParamsRoundTrip) {
  const std::string path = dir_.path() + "/round.clf";
  const LaserRecord flaser =
      MakeLaser(976052857.337530, Rigid2d(1.5, -2.25, 3.0), 180, static_cast<float>(-M_PI / 2),
                static_cast<float>(M_PI / 180), 8.0f, Rigid2d(-0.04, 0.0, 0.0));
  const LaserRecord flaser361 =
      MakeLaser(976052858.000001, Rigid2d(-7.0, 0.5, -1.0), 361, static_cast<float>(-M_PI / 2),
                static_cast<float>(M_PI / 360), 30.0f, Rigid2d());
  OdometryRecord odometry;
  odometry.timestamp = 976052857.5;
  odometry.robot_pose = Rigid2d(3.0, 4.0, -0.5);
  odometry.translational_velocity = 0.25;
  odometry.rotational_velocity = -0.125;
  {
    CarmenWriter writer(path);
    ASSERT_TRUE(writer.ok());
    writer.WriteParam("my_param", "some value", 976052857.0);
    writer.WriteLaser(flaser);
    writer.WriteOdometry(odometry);
    writer.WriteLaser(flaser361);
    ASSERT_TRUE(writer.Close());
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("FLASER 180 "), std::string::npos);
  EXPECT_NE(text.str().find(" 976052857.337530 fleetmap "), std::string::npos);
  EXPECT_EQ(text.str().find("ROBOTLASER1 "), std::string::npos);

  std::vector<CarmenRecord> records = ReadBack(path);
  std::vector<LaserRecord> lasers;
  std::vector<OdometryRecord> odometries;
  std::vector<ParamRecord> params;
  for (const CarmenRecord& record : records) {
    if (auto* l = std::get_if<LaserRecord>(&record)) lasers.push_back(*l);
    if (auto* o = std::get_if<OdometryRecord>(&record)) odometries.push_back(*o);
    if (auto* p = std::get_if<ParamRecord>(&record)) params.push_back(*p);
  }
  ASSERT_EQ(lasers.size(), 2u);
  ExpectSameLaser(lasers[0], flaser);
  ExpectSameLaser(lasers[1], flaser361);
  ASSERT_EQ(odometries.size(), 1u);
  EXPECT_DOUBLE_EQ(odometries[0].timestamp, odometry.timestamp);
  EXPECT_THAT(odometries[0].robot_pose, IsNearPose(odometry.robot_pose, 1e-6, 1e-6));
  EXPECT_DOUBLE_EQ(odometries[0].translational_velocity, 0.25);
  EXPECT_DOUBLE_EQ(odometries[0].rotational_velocity, -0.125);
  ASSERT_GE(params.size(), 1u);
  EXPECT_EQ(params[0].name, "my_param");
  EXPECT_EQ(params[0].value, "some value");
}

TEST_F(CarmenWriterTest, OtherFieldsOfViewBecomeRobotLaser) {
  const std::string path = dir_.path() + "/wide.clf";
  // A 270 degree scanner with a mount 0.2 m ahead, turned by 0.1 rad.
  const LaserRecord wide =
      MakeLaser(12.25, Rigid2d(1.0, 2.0, 0.3), 541, static_cast<float>(-3 * M_PI / 4),
                static_cast<float>(M_PI / 360), 20.0f, Rigid2d(0.2, 0.0, 0.1));
  {
    CarmenWriter writer(path, "robot one");
    writer.WriteLaser(wide);
    ASSERT_TRUE(writer.Close());
  }
  std::vector<CarmenRecord> records = ReadBack(path);
  std::vector<LaserRecord> lasers;
  for (const CarmenRecord& record : records) {
    if (auto* l = std::get_if<LaserRecord>(&record)) lasers.push_back(*l);
  }
  ASSERT_EQ(lasers.size(), 1u);
  ExpectSameLaser(lasers[0], wide);
}

TEST_F(CarmenWriterTest, UnwritablePathReportsFailure) {
  CarmenWriter writer(dir_.path() + "/no/such/dir/log.clf");
  EXPECT_FALSE(writer.ok());
}

}  // namespace
}  // namespace fleetmap

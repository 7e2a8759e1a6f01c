#include "shared/io/carmen_reader.h"

#include <bzlib.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

class CarmenReaderTest : public ::testing::Test {
 protected:
  std::string WritePlain(const std::string& name, const std::string& text) {
    const std::string path = dir_.path() + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::string WriteGzip(const std::string& name, const std::string& text) {
    const std::string path = dir_.path() + "/" + name;
    gzFile file = gzopen(path.c_str(), "wb");
    EXPECT_NE(file, nullptr);
    EXPECT_EQ(gzwrite(file, text.data(), static_cast<unsigned>(text.size())),
              static_cast<int>(text.size()));
    gzclose(file);
    return path;
  }
  std::string WriteBzip2(const std::string& name, const std::string& text) {
    std::vector<char> out(text.size() + text.size() / 100 + 1000);
    unsigned out_size = static_cast<unsigned>(out.size());
    std::string copy = text;
    EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &out_size, copy.data(),
                                       static_cast<unsigned>(copy.size()), 9, 0, 0),
              BZ_OK);
    out.resize(out_size);
    const std::string path = dir_.path() + "/" + name;
    std::ofstream(path, std::ios::binary).write(out.data(), static_cast<long>(out.size()));
    return path;
  }

  // Reads every record; returns false (with error) when the reader stops on an error.
  bool ReadAll(const std::string& path, std::vector<CarmenRecord>* records, std::string* error,
               const CarmenReaderOptions& options = CarmenReaderOptions()) {
    reader_ = CarmenReader::Open(path, options, error);
    if (!reader_) return false;
    CarmenRecord record;
    while (reader_->Next(&record)) records->push_back(record);
    *error = reader_->error();
    return error->empty();
  }

  const testing::ScopedTempDir dir_{"fleetmap-carmen-reader"};
  std::unique_ptr<CarmenReader> reader_;
};

// A FLASER line with `n` beams of `range`, both poses given.
std::string Flaser(int n, const std::string& range, const std::string& laser_pose,
                   const std::string& robot_pose, const std::string& ipc) {
  std::string line = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) line += " " + range;
  return line + " " + laser_pose + " " + robot_pose + " " + ipc + " nohost 0.5\n";
}

const char kSmallLog[] =
    "# a comment\n"
    "PARAM robot_frontlaser_offset 0.0 nohost 0\n"
    "ODOM 1.000000 2.000000 0.500000 0.3 0.1 0.0 976052857.337284 nohost 0.000000\n"
    "SONAR 1 2 3\n"
    "\n"
    "FLASER 4 1.0 2.5 81.83 3.0 1.0 2.0 0.5 1.0 2.0 0.5 976052857.337530 nohost 0.000246\n"
    "ROBOTLASER1 0 -1.570796 3.141593 0.785398 81.9 0.01 0 5 1 2 3 81.85 4 2 0.7 0.8 "
    "0.42 0 0 0 0 0 0.2 0 0 0 0 1232658478.161285 zoidberg2 -0.055208\n";

void ExpectSmallLog(const std::vector<CarmenRecord>& records) {
  ASSERT_EQ(records.size(), 4u);
  const auto& param = std::get<ParamRecord>(records[0]);
  EXPECT_EQ(param.name, "robot_frontlaser_offset");
  EXPECT_EQ(param.value, "0.0");

  const auto& odometry = std::get<OdometryRecord>(records[1]);
  EXPECT_DOUBLE_EQ(odometry.timestamp, 976052857.337284);
  EXPECT_THAT(odometry.robot_pose, IsNearPose(Rigid2d(1.0, 2.0, 0.5), 1e-12, 1e-12));
  EXPECT_DOUBLE_EQ(odometry.translational_velocity, 0.3);
  EXPECT_DOUBLE_EQ(odometry.rotational_velocity, 0.1);

  const auto& flaser = std::get<LaserRecord>(records[2]);
  EXPECT_DOUBLE_EQ(flaser.scan.timestamp, 976052857.337530);
  EXPECT_DOUBLE_EQ(flaser.logger_timestamp, 0.000246);
  ASSERT_EQ(flaser.scan.size(), 4);
  EXPECT_FLOAT_EQ(flaser.scan.ranges[0], 1.0f);
  EXPECT_FLOAT_EQ(flaser.scan.ranges[1], 2.5f);
  EXPECT_FALSE(flaser.scan.IsReturn(2));  // 81.83: SICK overflow code
  EXPECT_FLOAT_EQ(flaser.scan.ranges[3], 3.0f);
  // Four beams over 180 degrees from -90: 45 degree steps.
  EXPECT_FLOAT_EQ(flaser.scan.angle_min, static_cast<float>(-M_PI / 2));
  EXPECT_FLOAT_EQ(flaser.scan.angle_increment, static_cast<float>(M_PI / 4));
  EXPECT_THAT(flaser.robot_pose, IsNearPose(Rigid2d(1.0, 2.0, 0.5), 1e-12, 1e-12));
  EXPECT_THAT(flaser.scan.sensor_in_robot, IsNearPose(Rigid2d(), 1e-12, 1e-12));

  const auto& robot_laser = std::get<LaserRecord>(records[3]);
  EXPECT_DOUBLE_EQ(robot_laser.scan.timestamp, 1232658478.161285);
  ASSERT_EQ(robot_laser.scan.size(), 5);
  EXPECT_FLOAT_EQ(robot_laser.scan.angle_min, -1.570796f);
  EXPECT_FLOAT_EQ(robot_laser.scan.angle_increment, 0.785398f);
  EXPECT_FLOAT_EQ(robot_laser.scan.ranges[2], 3.0f);
  EXPECT_FALSE(robot_laser.scan.IsReturn(3));  // 81.85 >= the 50 m default
  // Laser 0.42 m ahead of a robot at the origin.
  EXPECT_THAT(robot_laser.scan.sensor_in_robot, IsNearPose(Rigid2d(0.42, 0.0, 0.0), 1e-9, 1e-9));
  EXPECT_THAT(robot_laser.robot_pose, IsNearPose(Rigid2d(), 1e-12, 1e-12));
}

TEST_F(CarmenReaderTest, ReadsEveryMessageTypeFromPlainText) {
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("small.clf", kSmallLog), &records, &error)) << error;
  ExpectSmallLog(records);
  EXPECT_EQ(reader_->skipped_lines(), 0);
  EXPECT_EQ(reader_->line_number(), 7);
  const auto& counts = reader_->message_counts();
  EXPECT_EQ(counts.at("#"), 1);
  EXPECT_EQ(counts.at("SONAR"), 1);
  EXPECT_EQ(counts.at("FLASER"), 1);
  EXPECT_EQ(counts.at("ROBOTLASER1"), 1);
}

TEST_F(CarmenReaderTest, ReadsGzipAndBzip2ByContentNotName) {
  for (const std::string& path :
       {WriteGzip("small.clf.gz", kSmallLog), WriteBzip2("small.clf.bz2", kSmallLog),
        WriteGzip("gzip-named.log", kSmallLog), WriteBzip2("bzip2-named.txt", kSmallLog)}) {
    SCOPED_TRACE(path);
    std::vector<CarmenRecord> records;
    std::string error;
    ASSERT_TRUE(ReadAll(path, &records, &error)) << error;
    ExpectSmallLog(records);
  }
}

TEST_F(CarmenReaderTest, ReadsLargeCompressedLogsAcrossBufferBoundaries) {
  std::string text;
  for (int i = 0; i < 1500; ++i) {
    text += Flaser(361, "12.345", "1 2 3", "1 2 3", std::to_string(1000 + i) + ".000001");
  }
  for (const std::string& path : {WritePlain("big.clf", text), WriteGzip("big.clf.gz", text),
                                  WriteBzip2("big.clf.bz2", text)}) {
    SCOPED_TRACE(path);
    std::vector<CarmenRecord> records;
    std::string error;
    ASSERT_TRUE(ReadAll(path, &records, &error)) << error;
    ASSERT_EQ(records.size(), 1500u);
    const auto& last = std::get<LaserRecord>(records.back());
    EXPECT_DOUBLE_EQ(last.scan.timestamp, 2499.000001);
    EXPECT_EQ(last.scan.size(), 361);
    // 361 beams: 0.5 degree steps covering -90..+90.
    EXPECT_NEAR(last.scan.angle(360), M_PI / 2, 1e-6);
  }
}

TEST_F(CarmenReaderTest, ConcatenatedCompressedStreamsReadAsOne) {
  const std::string first = Flaser(2, "1", "0 0 0", "0 0 0", "1.0");
  const std::string second = Flaser(2, "2", "0 0 0", "0 0 0", "2.0");
  const std::string gz_a = WriteGzip("a.gz", first);
  const std::string gz_b = WriteGzip("b.gz", second);
  const std::string bz_a = WriteBzip2("a.bz2", first);
  const std::string bz_b = WriteBzip2("b.bz2", second);
  for (const auto& [a, b] : {std::pair(gz_a, gz_b), std::pair(bz_a, bz_b)}) {
    std::ifstream in_a(a, std::ios::binary);
    std::ifstream in_b(b, std::ios::binary);
    const std::string joined = dir_.path() + "/joined";
    std::ofstream(joined, std::ios::binary) << in_a.rdbuf() << in_b.rdbuf();
    std::vector<CarmenRecord> records;
    std::string error;
    ASSERT_TRUE(ReadAll(joined, &records, &error)) << error;
    EXPECT_EQ(records.size(), 2u) << a;
  }
}

TEST_F(CarmenReaderTest, FlaserAngleConventionFollowsSources) {
  const std::string text =
      Flaser(180, "1", "0 0 0", "0 0 0", "1") + Flaser(360, "1", "0 0 0", "0 0 0", "2") +
      Flaser(361, "1", "0 0 0", "0 0 0", "3") + Flaser(181, "1", "0 0 0", "0 0 0", "4");
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("angles.clf", text), &records, &error)) << error;
  ASSERT_EQ(records.size(), 4u);
  const double deg = M_PI / 180;
  const double expected_increment[] = {1 * deg, 0.5 * deg, 0.5 * deg, 1 * deg};
  const double expected_last[] = {89 * deg, 89.5 * deg, 90 * deg, 90 * deg};
  for (size_t i = 0; i < 4; ++i) {
    const LaserScan& scan = std::get<LaserRecord>(records[i]).scan;
    EXPECT_NEAR(scan.angle_min, -90 * deg, 1e-6);
    EXPECT_NEAR(scan.angle_increment, expected_increment[i], 1e-7);
    EXPECT_NEAR(scan.angle(scan.size() - 1), expected_last[i], 1e-5);
  }
}

TEST_F(CarmenReaderTest, MountOffsetFromDifferingPoses) {
  // fr079-style: the laser 4 cm behind a robot heading along -x.
  const std::string text =
      Flaser(2, "1", "-2.994295 8.292039 -3.120965", "-3.034287 8.291214 -3.120965", "1");
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("mount.clf", text), &records, &error)) << error;
  const auto& laser = std::get<LaserRecord>(records.at(0));
  EXPECT_THAT(laser.scan.sensor_in_robot, IsNearPose(Rigid2d(-0.04, 0.0, 0.0), 1e-4, 1e-9));
  EXPECT_THAT(laser.robot_pose * laser.scan.sensor_in_robot,
              IsNearPose(laser.laser_pose, 1e-9, 1e-9));
}

TEST_F(CarmenReaderTest, MountOffsetFromParamWhenPosesCoincide) {
  const std::string text = "PARAM robot_frontlaser_offset -0.04 1.0 host 1.0\n" +
                           Flaser(2, "1", "5 6 1.5707963", "5 6 1.5707963", "2");
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("param-mount.clf", text), &records, &error)) << error;
  ASSERT_EQ(records.size(), 2u);
  const auto& laser = std::get<LaserRecord>(records[1]);
  EXPECT_THAT(laser.scan.sensor_in_robot, IsNearPose(Rigid2d(-0.04, 0.0, 0.0), 1e-12, 1e-12));
  EXPECT_THAT(laser.laser_pose, IsNearPose(Rigid2d(5.0, 5.96, 1.5707963), 1e-6, 1e-9));
}

TEST_F(CarmenReaderTest, MaxRangeRulesAndParamOverride) {
  const std::string text =
      Flaser(2, "49.99", "0 0 0", "0 0 0", "1") + Flaser(2, "50.00", "0 0 0", "0 0 0", "2") +
      "PARAM robot_front_laser_max 80.99 3 host 3\n" + Flaser(2, "60", "0 0 0", "0 0 0", "4") +
      Flaser(2, "81.91", "0 0 0", "0 0 0", "5");
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("max.clf", text), &records, &error)) << error;
  ASSERT_EQ(records.size(), 5u);
  EXPECT_TRUE(std::get<LaserRecord>(records[0]).scan.IsReturn(0));
  EXPECT_FALSE(std::get<LaserRecord>(records[1]).scan.IsReturn(0));
  EXPECT_TRUE(std::get<LaserRecord>(records[3]).scan.IsReturn(0));
  EXPECT_FALSE(std::get<LaserRecord>(records[4]).scan.IsReturn(0));

  // A configured cap, with the PARAM ignored.
  CarmenReaderOptions options;
  options.max_range = 30.0;
  options.max_range_from_params = false;
  records.clear();
  ASSERT_TRUE(ReadAll(WritePlain("max.clf", text), &records, &error, options)) << error;
  EXPECT_FALSE(std::get<LaserRecord>(records[3]).scan.IsReturn(0));
  EXPECT_FLOAT_EQ(std::get<LaserRecord>(records[3]).scan.range_max, 30.0f);
}

TEST_F(CarmenReaderTest, ParamValuesWithAndWithoutTrailer) {
  const std::string text =
      "PARAM a 1.5\n"
      "PARAM b some/path with space 1071078718.46 merci 1071078718.46\n"
      "PARAM c 0.0 nohost 0\n";
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("params.clf", text), &records, &error)) << error;
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(std::get<ParamRecord>(records[0]).value, "1.5");
  EXPECT_EQ(std::get<ParamRecord>(records[1]).value, "some/path with space");
  EXPECT_EQ(std::get<ParamRecord>(records[2]).value, "0.0");
}

TEST_F(CarmenReaderTest, WindowsLineEndingsAndNoFinalNewline) {
  std::string text = Flaser(2, "1", "0 0 0", "0 0 0", "1");
  text.insert(text.size() - 1, "\r");
  text += "ODOM 1 2 3 0 0 0 5.5 host 0";  // no final newline
  std::vector<CarmenRecord> records;
  std::string error;
  ASSERT_TRUE(ReadAll(WritePlain("crlf.clf", text), &records, &error)) << error;
  ASSERT_EQ(records.size(), 2u);
  EXPECT_DOUBLE_EQ(std::get<OdometryRecord>(records[1]).timestamp, 5.5);
}

TEST_F(CarmenReaderTest, MissingFileIsAnError) {
  std::string error;
  EXPECT_EQ(CarmenReader::Open(dir_.path() + "/nope.clf", CarmenReaderOptions(), &error), nullptr);
  EXPECT_NE(error.find("nope.clf"), std::string::npos) << error;
}

}  // namespace
}  // namespace fleetmap

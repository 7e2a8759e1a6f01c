// Reads the public benchmark logs in ../shared/data (skipped when absent).

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "shared/io/carmen_reader.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

struct LogSummary {
  long lasers = 0;
  long odometry = 0;
  long params = 0;
  long no_returns = 0;
  long beams = 0;
  std::map<int, long> beam_counts;
  LaserRecord first_laser;
  std::string error;
};

LogSummary Summarize(const std::string& path) {
  LogSummary summary;
  auto reader = CarmenReader::Open(path, CarmenReaderOptions(), &summary.error);
  if (!reader) return summary;
  CarmenRecord record;
  while (reader->Next(&record)) {
    if (auto* laser = std::get_if<LaserRecord>(&record)) {
      if (summary.lasers == 0) summary.first_laser = *laser;
      ++summary.lasers;
      ++summary.beam_counts[laser->scan.size()];
      summary.beams += laser->scan.size();
      summary.no_returns += laser->scan.size() - laser->scan.CountReturns();
    } else if (std::holds_alternative<OdometryRecord>(record)) {
      ++summary.odometry;
    } else {
      ++summary.params;
    }
  }
  summary.error = reader->error();
  return summary;
}

TEST(CarmenDataTest, IntelHas13631Scans) {
  FLEETMAP_REQUIRE_DATA(path, "intel-lab/intel.clf.bz2");
  const LogSummary summary = Summarize(path);
  ASSERT_EQ(summary.error, "");
  EXPECT_EQ(summary.lasers, 13631);
  EXPECT_EQ(summary.odometry, 26915);
  EXPECT_EQ(summary.params, 2);
  EXPECT_EQ(summary.beam_counts.at(180), 13631);
  // 68,313 readings of 81.83 m are SICK overflow codes, not walls.
  EXPECT_EQ(summary.no_returns, 68313);
  EXPECT_DOUBLE_EQ(summary.first_laser.scan.timestamp, 976052857.337530);
  EXPECT_THAT(summary.first_laser.scan.sensor_in_robot, IsNearPose(Rigid2d(), 1e-12, 1e-12));
}

TEST(CarmenDataTest, AcesHas7374ScansWith50MetreSaturation) {
  FLEETMAP_REQUIRE_DATA(path, "aces/aces.clf.bz2");
  const LogSummary summary = Summarize(path);
  ASSERT_EQ(summary.error, "");
  EXPECT_EQ(summary.lasers, 7374);
  EXPECT_EQ(summary.odometry, 7375);
  EXPECT_EQ(summary.no_returns, 11139);  // the readings of exactly 50.00 m
}

TEST(CarmenDataTest, Fr079RecoversTheMinus4CentimetreMount) {
  FLEETMAP_REQUIRE_DATA(path, "fr079/fr079.clf.bz2");
  const LogSummary summary = Summarize(path);
  ASSERT_EQ(summary.error, "");
  EXPECT_EQ(summary.lasers, 4934);
  EXPECT_EQ(summary.odometry, 8951);
  EXPECT_EQ(summary.params, 187);
  EXPECT_EQ(summary.beam_counts.at(360), 4934);
  EXPECT_THAT(summary.first_laser.scan.sensor_in_robot,
              IsNearPose(Rigid2d(-0.04, 0.0, 0.0), 2e-3, 1e-9));
  EXPECT_NEAR(summary.first_laser.scan.angle_increment, M_PI / 360, 1e-7);
}

TEST(CarmenDataTest, MitCsailHas361BeamScansAndNoOdometry) {
  FLEETMAP_REQUIRE_DATA(path, "mit-csail/mit-csail.clf.bz2");
  const LogSummary summary = Summarize(path);
  ASSERT_EQ(summary.error, "");
  EXPECT_EQ(summary.lasers, 1988);
  EXPECT_EQ(summary.odometry, 0);
  EXPECT_EQ(summary.beam_counts.at(361), 1988);
  EXPECT_NEAR(summary.first_laser.scan.angle(360), M_PI / 2, 1e-5);
}

TEST(CarmenDataTest, FrClinicRobotLaserHas22CentimetreMount) {
  FLEETMAP_REQUIRE_DATA(path, "fr-clinic/fr-clinic_robotlaser.clf.bz2");
  const LogSummary summary = Summarize(path);
  ASSERT_EQ(summary.error, "");
  EXPECT_EQ(summary.lasers, 6917);
  EXPECT_EQ(summary.beam_counts.at(180), 5169);
  EXPECT_EQ(summary.beam_counts.at(181), 1748);
  EXPECT_THAT(summary.first_laser.scan.sensor_in_robot,
              IsNearPose(Rigid2d(0.22, 0.0, 0.0), 1e-6, 1e-6));
}

TEST(CarmenDataTest, CorrectedAndDerivedLogsReadWithoutErrors) {
  const std::pair<const char*, long> logs[] = {
      {"intel-lab/intel-corrected.log.gz", 910},
      {"aces/aces-corrected.log.gz", 440},
      {"fr079/freiburg-079-corrected.log.gz", 4791},
      {"mit-csail/csail-corrected.log.gz", 406},
      {"mit-killian/mit-killian_from-mola-rawlog.clf.gz", 17480},
      {"radish-corrected/seattle-corrected.log.gz", 241},
  };
  for (const auto& [relative, lasers] : logs) {
    const auto path = testing::DataFile(relative);
    if (!path) continue;
    SCOPED_TRACE(relative);
    const LogSummary summary = Summarize(*path);
    EXPECT_EQ(summary.error, "");
    EXPECT_EQ(summary.lasers, lasers);
  }
}

}  // namespace
}  // namespace fleetmap

#include "tests/agent/synthetic_drive.h"

#include <cmath>

#include "shared/io/carmen_writer.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

SegmentWorld SyntheticRoom() {
  SegmentWorld world = BoxWorld({-1.0, -1.0}, {11.0, 7.0});
  AddBox({2.0, 2.0}, {3.0, 2.5}, &world);
  AddBox({6.0, 3.5}, {6.5, 5.0}, &world);
  AddBox({8.5, 1.0}, {9.0, 1.5}, &world);
  return world;
}

namespace {

// A rounded rectangle loop: (0,0) -> (9,0) -> (9,5) -> (0,5) -> (0,0), 0.1 m per step.
Rigid2d PoseAt(int step) {
  const double perimeter = 2.0 * (9.0 + 5.0);
  double s = std::fmod(0.1 * step, perimeter);
  if (s < 9.0) return Rigid2d(s, 0.0, 0.0);
  s -= 9.0;
  if (s < 5.0) return Rigid2d(9.0, s, M_PI / 2);
  s -= 5.0;
  if (s < 9.0) return Rigid2d(9.0 - s, 5.0, M_PI);
  s -= 9.0;
  return Rigid2d(0.0, 5.0 - s, -M_PI / 2);
}

}  // namespace

std::vector<SensorEvent> SyntheticDrive(int scans, double start_time) {
  const SegmentWorld world = SyntheticRoom();
  std::vector<SensorEvent> events;
  for (int i = 0; i < scans; ++i) {
    const double t = start_time + 0.1 * i;
    const Rigid2d pose = PoseAt(i);
    SensorEvent odometry;
    odometry.timestamp = t;
    odometry.odometry = OdometryRecord{t, pose, 1.0, 0.0};
    events.push_back(odometry);
    SensorEvent laser;
    laser.timestamp = t;
    LaserRecord record;
    record.scan = SimulateScan(world, pose);
    record.scan.timestamp = t;
    record.robot_pose = pose;
    record.laser_pose = pose;
    record.logger_timestamp = t;
    laser.laser = record;
    laser.ground_truth = pose;
    events.push_back(laser);
  }
  return events;
}

bool WriteSyntheticLog(const std::string& path, int scans, double start_time) {
  CarmenWriter writer(path);
  if (!writer.ok()) return false;
  for (const SensorEvent& event : SyntheticDrive(scans, start_time)) {
    if (event.odometry) writer.WriteOdometry(*event.odometry);
    if (event.laser) writer.WriteLaser(*event.laser);
  }
  return writer.Close();
}

}  // namespace fleetmap::testing

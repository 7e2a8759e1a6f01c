#ifndef FLEETMAP_TESTS_AGENT_SYNTHETIC_DRIVE_H_
#define FLEETMAP_TESTS_AGENT_SYNTHETIC_DRIVE_H_

#include <string>
#include <vector>

#include "robot_agent/agent/sensor_source.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

// The room the synthetic robot drives in (its walls are the ground truth of its map).
SegmentWorld SyntheticRoom();

// A robot driving a loop in a 12 m x 8 m room with a few boxes, exact odometry, one scan per
// 0.1 s (and 0.1 m). Known answer: the scan poses are the true poses.
std::vector<SensorEvent> SyntheticDrive(int scans, double start_time = 1000.0);

// The same drive as a CARMEN log (FLASER + ODOM lines); false when the file cannot be written.
bool WriteSyntheticLog(const std::string& path, int scans, double start_time = 1000.0);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_AGENT_SYNTHETIC_DRIVE_H_

#ifndef FLEETMAP_SHARED_IO_CARMEN_LOG_H_
#define FLEETMAP_SHARED_IO_CARMEN_LOG_H_

#include <string>
#include <variant>

#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// One ODOM line: raw wheel odometry.
struct OdometryRecord {
  double timestamp = 0.0;  // ipc_timestamp, seconds
  Rigid2d robot_pose;      // odometry frame
  double translational_velocity = 0.0;
  double rotational_velocity = 0.0;
};

// One FLASER or ROBOTLASER1 line. `scan.timestamp` is the ipc_timestamp, the key the
// benchmark relation files use; `scan.sensor_in_robot` is the mount offset derived from the
// line's laser and robot poses (or the log's PARAM, when the line's poses coincide).
struct LaserRecord {
  LaserScan scan;
  Rigid2d robot_pose;  // odometry pose of the robot centre at the scan
  Rigid2d laser_pose;  // odometry pose of the laser at the scan
  double logger_timestamp = 0.0;
};

// One PARAM line.
struct ParamRecord {
  std::string name;
  std::string value;
};

using CarmenRecord = std::variant<OdometryRecord, LaserRecord, ParamRecord>;

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_LOG_H_

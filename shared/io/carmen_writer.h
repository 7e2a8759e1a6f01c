#ifndef FLEETMAP_SHARED_IO_CARMEN_WRITER_H_
#define FLEETMAP_SHARED_IO_CARMEN_WRITER_H_

#include <fstream>
#include <string>

#include "shared/io/carmen_log.h"

namespace fleetmap {

// Writes FLASER + ODOM (+ PARAM) lines that CarmenReader reads back. FLASER assumes the
// reader's convention (180 degrees field of view, see SOURCES.md); scans with another field of
// view are written as ROBOTLASER1 lines, which carry their own angles.
class CarmenWriter {
 public:
  // Check ok() after construction.
  CarmenWriter(const std::string& path, const std::string& hostname = "fleetmap");
  bool ok() const { return static_cast<bool>(out_); }

  void WriteParam(const std::string& name, const std::string& value, double timestamp);
  void WriteOdometry(const OdometryRecord& odometry);
  void WriteLaser(const LaserRecord& laser);
  // Flushes; returns false when any write failed.
  bool Close();

 private:
  std::ofstream out_;
  std::string hostname_;
  double first_timestamp_ = -1.0;
  // The no-return value announced by the last PARAM robot_front_laser_max (0: none yet).
  float written_max_range_ = 0.0f;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_WRITER_H_

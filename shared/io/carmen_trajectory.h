#ifndef FLEETMAP_SHARED_IO_CARMEN_TRAJECTORY_H_
#define FLEETMAP_SHARED_IO_CARMEN_TRAJECTORY_H_

#include <string>

#include "shared/core/trajectory.h"
#include "shared/io/carmen_reader.h"

namespace fleetmap {

// The raw-odometry trajectory of a CARMEN log: one pose per laser scan (FLASER or
// ROBOTLASER1), stamped with the scan's ipc_timestamp (the key of benchmark relation files),
// holding the scan's robot pose, in log order. Raw logs are not always time-ordered (intel has
// 631 scans stamped earlier than the scan before), so neither is this trajectory. Returns false
// with the reader's error on a malformed log.
bool ReadOdometryTrajectory(const std::string& log_path, const CarmenReaderOptions& options,
                            Trajectory* trajectory, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_TRAJECTORY_H_

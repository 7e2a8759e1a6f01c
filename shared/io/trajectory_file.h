#ifndef FLEETMAP_SHARED_IO_TRAJECTORY_FILE_H_
#define FLEETMAP_SHARED_IO_TRAJECTORY_FILE_H_

#include <string>
#include <vector>

#include "shared/core/trajectory.h"

namespace fleetmap {

// Text format: one line per pose, "timestamp x y theta" (seconds, metres, radians); '#' lines
// are comments. Timestamps are written with microsecond precision so they match CARMEN
// ipc_timestamps exactly.
bool WriteTrajectory(const std::string& path, const Trajectory& trajectory, std::string* error);
bool ReadTrajectory(const std::string& path, Trajectory* trajectory, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_TRAJECTORY_FILE_H_

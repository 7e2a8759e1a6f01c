#ifndef FLEETMAP_MAP_SERVER_STORE_POSE_BLOB_H_
#define FLEETMAP_MAP_SERVER_STORE_POSE_BLOB_H_

#include <string>

#include "shared/core/trajectory.h"

namespace fleetmap {

// Stamped poses as a blob of little-endian doubles (timestamp, x, y, theta) per pose.
std::string PackPoses(const Trajectory& poses);
// False when the blob's size is not a whole number of poses.
bool UnpackPoses(const std::string& blob, Trajectory* poses);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_POSE_BLOB_H_

#include "map_server/store/pose_blob.h"

#include <cstring>

namespace fleetmap {
namespace {
constexpr size_t kPoseBytes = 4 * sizeof(double);
}  // namespace

// Hosts we build for are little-endian, so the doubles are copied as they are.
std::string PackPoses(const Trajectory& poses) {
  std::string blob(poses.size() * kPoseBytes, '\0');
  char* out = blob.data();
  for (const StampedPose& p : poses) {
    const double values[4] = {p.timestamp, p.pose.x(), p.pose.y(), p.pose.rotation()};
    std::memcpy(out, values, kPoseBytes);
    out += kPoseBytes;
  }
  return blob;
}

bool UnpackPoses(const std::string& blob, Trajectory* poses) {
  if (blob.size() % kPoseBytes != 0) return false;
  poses->clear();
  poses->reserve(blob.size() / kPoseBytes);
  for (size_t offset = 0; offset < blob.size(); offset += kPoseBytes) {
    double v[4];
    std::memcpy(v, blob.data() + offset, kPoseBytes);
    poses->push_back(StampedPose{v[0], Rigid2d(v[1], v[2], v[3])});
  }
  return true;
}

}  // namespace fleetmap

#include "shared/io/trajectory_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "shared/io/number_rows_file.h"

namespace fleetmap {
namespace {

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

}  // namespace

bool WriteTrajectory(const std::string& path, const Trajectory& trajectory, std::string* error) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) return Fail(error, path + ": cannot write: " + std::strerror(errno));
  std::fputs("# timestamp x y theta (seconds, metres, radians)\n", file.get());
  for (const StampedPose& stamped : trajectory) {
    std::fprintf(file.get(), "%.6f %.6f %.6f %.9f\n", stamped.timestamp, stamped.pose.x(),
                 stamped.pose.y(), stamped.pose.rotation());
  }
  if (std::fflush(file.get()) != 0 || std::ferror(file.get())) {
    return Fail(error, path + ": write failed: " + std::strerror(errno));
  }
  return true;
}

// Poses are kept in file order, even when timestamps go backwards: raw logs do that (intel has
// 631 laser scans whose ipc_timestamp is earlier than the previous scan's, by up to 0.9 s), and
// the metrics look poses up by time anyway.
bool ReadTrajectory(const std::string& path, Trajectory* trajectory, std::string* error) {
  trajectory->clear();
  return ReadNumberRows(
      path, 4, "timestamp x y theta",
      [&](const double* v) {
        trajectory->push_back(StampedPose{v[0], Rigid2d(v[1], v[2], v[3])});
      },
      error);
}

}  // namespace fleetmap

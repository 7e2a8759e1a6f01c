#include "shared/io/carmen_trajectory.h"

#include <memory>

namespace fleetmap {

bool ReadOdometryTrajectory(const std::string& log_path, const CarmenReaderOptions& options,
                            Trajectory* trajectory, std::string* error) {
  std::unique_ptr<CarmenReader> reader = CarmenReader::Open(log_path, options, error);
  if (!reader) return false;
  trajectory->clear();
  CarmenRecord record;
  while (reader->Next(&record)) {
    if (const auto* laser = std::get_if<LaserRecord>(&record)) {
      trajectory->push_back(StampedPose{laser->scan.timestamp, laser->robot_pose});
    }
  }
  if (!reader->error().empty()) {
    if (error) *error = reader->error();
    return false;
  }
  return true;
}

}  // namespace fleetmap

#include "shared/tools/odometry_map.h"

#include <filesystem>
#include <memory>
#include <system_error>

#include "shared/io/map_file.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap {

bool BuildOdometryMap(const std::string& log_path, const CarmenReaderOptions& reader_options,
                      const OdometryMapOptions& options, OccupancyGrid* grid,
                      Trajectory* trajectory, std::string* error,
                      const std::function<void(long scans)>& progress) {
  std::unique_ptr<CarmenReader> reader = CarmenReader::Open(log_path, reader_options, error);
  if (!reader) return false;
  *grid = OccupancyGrid(options.grid);
  trajectory->clear();
  const long stride = options.scan_stride > 0 ? options.scan_stride : 1;
  long scans = 0;
  CarmenRecord record;
  while (reader->Next(&record)) {
    const auto* laser = std::get_if<LaserRecord>(&record);
    if (laser == nullptr) continue;
    trajectory->push_back(StampedPose{laser->scan.timestamp, laser->robot_pose});
    if (scans % stride == 0) grid->InsertScan(laser->scan, laser->robot_pose);
    ++scans;
    if (progress && scans % 1000 == 0) progress(scans);
  }
  if (!reader->error().empty()) {
    if (error) *error = reader->error();
    return false;
  }
  return true;
}

bool WriteOdometryMapOutputs(const std::string& dir, const OccupancyGrid& grid,
                             const Trajectory& trajectory, std::string* error) {
  std::error_code code;
  std::filesystem::create_directories(dir, code);
  if (code) {
    if (error) *error = dir + ": cannot create directory: " + code.message();
    return false;
  }
  const std::string stem = (std::filesystem::path(dir) / "map").string();
  return WriteMap(stem, grid, error) && WriteMapPng(stem + ".png", grid, error) &&
         WriteTrajectory((std::filesystem::path(dir) / "trajectory.txt").string(), trajectory,
                         error);
}

}  // namespace fleetmap

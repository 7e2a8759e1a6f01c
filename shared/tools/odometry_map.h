#ifndef FLEETMAP_SHARED_TOOLS_ODOMETRY_MAP_H_
#define FLEETMAP_SHARED_TOOLS_ODOMETRY_MAP_H_

#include <functional>
#include <string>

#include "shared/core/occupancy_grid.h"
#include "shared/core/trajectory.h"
#include "shared/io/carmen_reader.h"

namespace fleetmap {

struct OdometryMapOptions {
  OccupancyGridOptions grid;
  // Insert every n-th scan only (1: all), for a quick look at a long log.
  int scan_stride = 1;
};

// Streams a CARMEN log and inserts every laser scan into `grid` at its raw-odometry robot pose;
// `trajectory` gets one pose per laser scan (ipc_timestamp, robot pose), inserted or not.
// `progress` (may be empty) is called every 1000 scans with the count so far.
bool BuildOdometryMap(const std::string& log_path, const CarmenReaderOptions& reader_options,
                      const OdometryMapOptions& options, OccupancyGrid* grid,
                      Trajectory* trajectory, std::string* error,
                      const std::function<void(long scans)>& progress = {});

// Writes DIR/map.pgm, DIR/map.yaml, DIR/map.png and DIR/trajectory.txt (creating DIR).
bool WriteOdometryMapOutputs(const std::string& dir, const OccupancyGrid& grid,
                             const Trajectory& trajectory, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_TOOLS_ODOMETRY_MAP_H_

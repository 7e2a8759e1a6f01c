#ifndef FLEETMAP_ROBOT_AGENT_SLAM_LOG_RUNNER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_LOG_RUNNER_H_

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "robot_agent/slam/local_slam.h"
#include "robot_agent/slam/packed_submap.h"
#include "shared/core/laser_scan.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

// A CARMEN log in memory, checked and ready to feed to a backend.
struct SlamLog {
  std::vector<LaserScan> scans;      // in time order, stamped with their ipc_timestamp
  std::vector<long> scan_lines;      // line of each scan in the file, for messages
  Trajectory odometry;               // one reading per scan, or from ODOM lines, or empty
  std::string odometry_source;       // "laser lines", "ODOM lines" or "none"
  std::vector<std::string> warnings; // things the user should know (printed by the tool)
};

struct SlamLogOptions {
  // Scans up to this much older than the newest scan before them are re-sorted into time order
  // (loggers interleave messages); a larger step back fails the load, or with skip_out_of_order
  // drops the scan with a warning.
  double max_reorder_seconds = 2.0;
  bool skip_out_of_order = false;
  // Passed to the CARMEN reader.
  bool skip_bad_lines = false;
};

// Reads and checks a CARMEN log (plain, .gz, .bz2); scans come out in timestamp order. Fails
// with a message naming the problem on an unreadable file, a log without laser scans, scans
// whose returns are all missing, or time going backwards by more than max_reorder_seconds. A log whose odometry never changes is accepted with a warning (the backend
// then matches without an odometry prior).
bool LoadSlamLog(const std::string& path, const SlamLogOptions& options, SlamLog* log,
                 std::string* error);

struct SlamRunResult {
  Trajectory trajectory;               // one pose per scan
  std::map<int64_t, PackedSubmap> submaps;  // latest version of every submap, by id
  double seconds = 0.0;                // wall time spent inside the backend
};

// Feeds the log to `slam` in time order. `progress(done, total)` is called now and then, and
// with done == total once every scan is in, before the backend finishes.
bool RunSlam(const SlamLog& log, LocalSlam* slam, SlamRunResult* result, std::string* error,
             const std::function<void(size_t, size_t)>& progress = nullptr);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_LOG_RUNNER_H_

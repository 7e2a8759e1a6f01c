#ifndef FLEETMAP_SHARED_TOOLS_LOG_SUMMARY_H_
#define FLEETMAP_SHARED_TOOLS_LOG_SUMMARY_H_

#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "shared/io/carmen_reader.h"

namespace fleetmap {

// What `fleetmap-log info` reports about a CARMEN log.
struct LogSummary {
  std::string path;
  long lines = 0;
  long skipped_lines = 0;
  std::string first_skipped_error;
  std::map<std::string, long> message_counts;  // per type, unknown types and "#" included
  long laser_scans = 0;
  long odometry_records = 0;
  std::map<int, long> beams_per_scan;  // beam count -> scans
  long readings = 0;
  long no_return_readings = 0;
  float max_return_range = 0.0f;  // the longest real return
  double first_timestamp = 0.0;   // ipc_timestamp of the first record with one
  double last_timestamp = 0.0;
  double laser_odometry_distance = 0.0;  // path length of the robot pose over laser records
  double odom_distance = 0.0;            // path length over ODOM records
  Rigid2d first_sensor_in_robot;
  std::vector<std::pair<std::string, std::string>> params;  // in log order
};

// Reads the whole log. `progress` (may be empty) is called every `progress_every` laser scans.
// Returns false with `error` when the log cannot be opened or has a malformed line (unless
// options.skip_bad_lines).
bool SummarizeLog(const std::string& path, const CarmenReaderOptions& options, LogSummary* summary,
                  std::string* error, const std::function<void(long scans)>& progress = {},
                  long progress_every = 5000);

// Human-readable report; prints at most `max_params` PARAM lines (all when negative).
void PrintLogSummary(const LogSummary& summary, int max_params, std::ostream& out);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_TOOLS_LOG_SUMMARY_H_

#include "robot_agent/localization/tool/log_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <variant>
#include <vector>

#include "shared/io/carmen_reader.h"
#include "shared/io/map_file.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap {

int RunLogCommand(const LogCommandOptions& options) {
  OccupancyGrid map;
  std::string error;
  if (!ReadMap(options.map_path, &map, &error)) {
    std::fprintf(stderr, "error: --map: %s\n", error.c_str());
    return 1;
  }
  CarmenReaderOptions reader_options;
  reader_options.max_range = options.max_range;
  std::unique_ptr<CarmenReader> reader =
      CarmenReader::Open(options.log_path, reader_options, &error);
  if (!reader) {
    std::fprintf(stderr, "error: --log: %s\n", error.c_str());
    return 1;
  }
  std::printf("map %s: %d x %d cells of %.3f m; start %s\n", options.map_path.c_str(), map.width(),
              map.height(), map.resolution(),
              options.localizer.initial_pose ? "known (Gaussian around --initial-pose)"
                                             : "unknown (global localization)");
  // Like fleetmap-slam: every scan in timestamp order (intel has 631 scans filed after newer
  // ones), read first, so a scan out of place is used rather than refused.
  std::vector<LaserRecord> lasers;
  CarmenRecord record;
  while (reader->Next(&record)) {
    if (auto* laser = std::get_if<LaserRecord>(&record)) lasers.push_back(std::move(*laser));
  }
  if (!reader->error().empty()) {
    std::fprintf(stderr, "error: %s\n", reader->error().c_str());
    return 1;
  }
  const bool in_order =
      std::is_sorted(lasers.begin(), lasers.end(), [](const LaserRecord& a, const LaserRecord& b) {
        return a.scan.timestamp < b.scan.timestamp;
      });
  if (!in_order) {
    std::stable_sort(lasers.begin(), lasers.end(), [](const LaserRecord& a, const LaserRecord& b) {
      return a.scan.timestamp < b.scan.timestamp;
    });
    std::printf("some scans came after newer ones in the file: all are used in timestamp order\n");
  }
  MclLocalizer localizer(map, options.localizer);
  const auto start = std::chrono::steady_clock::now();
  long scans = 0, refused = 0;
  double particles = 0.0;
  std::string refusal;
  for (const LaserRecord& laser : lasers) {
    // As the agent does with a log whose laser lines carry odometry: the reading at each scan.
    localizer.AddOdometry({laser.scan.timestamp, laser.robot_pose}, &refusal);
    if (!localizer.AddScan(laser.scan, &refusal)) {
      ++refused;
      continue;
    }
    particles += localizer.estimate().particle_count;
    if (++scans % 1000 == 0) std::fprintf(stderr, "\r%ld scans", scans);
  }
  std::fprintf(stderr, "\n");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!WriteTrajectory(options.out_path, localizer.trajectory(), &error)) {
    std::fprintf(stderr, "error: --out: %s\n", error.c_str());
    return 1;
  }
  std::printf(
      "%ld scans (%ld refused), %.1f s (%.0f scans/s, one core), %.0f particles on "
      "average\n%s\nwrote %s\n",
      scans, refused, seconds, seconds > 0 ? scans / seconds : 0.0,
      scans > 0 ? particles / scans : 0.0, localizer.Statistics().c_str(),
      options.out_path.c_str());
  return 0;
}

}  // namespace fleetmap

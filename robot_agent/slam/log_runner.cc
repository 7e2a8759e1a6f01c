#include "robot_agent/slam/log_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <variant>

#include "shared/io/carmen_reader.h"

namespace fleetmap {
namespace {

bool Moves(const Trajectory& odometry) {
  for (const StampedPose& reading : odometry) {
    const Rigid2d delta = odometry.front().pose.inverse() * reading.pose;
    if (delta.translation().norm() > 1e-6 || std::abs(delta.rotation()) > 1e-6) return true;
  }
  return false;
}

std::string Time(double t) {
  std::ostringstream out;
  out.precision(17);
  out << t;
  return out.str();
}

}  // namespace

bool LoadSlamLog(const std::string& path, const SlamLogOptions& options, SlamLog* log,
                 std::string* error) {
  *log = SlamLog();
  CarmenReaderOptions reader_options;
  reader_options.skip_bad_lines = options.skip_bad_lines;
  std::unique_ptr<CarmenReader> reader = CarmenReader::Open(path, reader_options, error);
  if (!reader) return false;
  Trajectory laser_odometry, odom_lines;
  long out_of_order = 0;
  long reordered = 0;
  double newest = 0.0;
  long newest_line = 0;
  long odom_out_of_order = 0;
  CarmenRecord record;
  while (reader->Next(&record)) {
    if (const auto* laser = std::get_if<LaserRecord>(&record)) {
      if (!std::isfinite(laser->scan.timestamp)) {
        *error = path + ":" + std::to_string(reader->line_number()) + ": laser scan with a non-finite timestamp";
        return false;
      }
      // Loggers write messages as they arrive, so a scan may follow a slightly newer one (intel
      // has 631, up to 0.9 s back); those are re-sorted below. A larger step back is corrupt.
      if (!log->scans.empty() && laser->scan.timestamp < newest - options.max_reorder_seconds) {
        if (!options.skip_out_of_order) {
          *error = path + ":" + std::to_string(reader->line_number()) + ": time goes backwards: scan at " +
                   Time(laser->scan.timestamp) + " is " + Time(newest - laser->scan.timestamp) +
                   " s older than an earlier scan (line " + std::to_string(newest_line) +
                   "); use --skip-out-of-order to drop such scans";
          return false;
        }
        ++out_of_order;
        continue;
      }
      if (!log->scans.empty() && laser->scan.timestamp < log->scans.back().timestamp) ++reordered;
      if (log->scans.empty() || laser->scan.timestamp > newest) {
        newest = laser->scan.timestamp;
        newest_line = reader->line_number();
      }
      log->scans.push_back(laser->scan);
      log->scan_lines.push_back(reader->line_number());
      laser_odometry.push_back({laser->scan.timestamp, laser->robot_pose});
    } else if (const auto* odom = std::get_if<OdometryRecord>(&record)) {
      if (!odom_lines.empty() && odom->timestamp < odom_lines.back().timestamp) {
        ++odom_out_of_order;
        continue;
      }
      odom_lines.push_back({odom->timestamp, odom->robot_pose});
    }
  }
  if (!reader->error().empty()) {
    *error = reader->error();
    return false;
  }
  if (reader->skipped_lines() > 0) {
    log->warnings.push_back("skipped " + std::to_string(reader->skipped_lines()) +
                            " malformed lines, the first: " + reader->first_skipped_error());
  }
  if (log->scans.empty()) {
    *error = path + ": no laser scans (FLASER or ROBOTLASER1 lines) in the log: nothing to map";
    return false;
  }
  long with_returns = 0;
  for (const LaserScan& scan : log->scans) with_returns += scan.HasReturns() ? 1 : 0;
  if (with_returns == 0) {
    *error = path + ": all " + std::to_string(log->scans.size()) +
             " laser scans have no returns (every reading missing or out of range): nothing to map";
    return false;
  }
  if (with_returns < static_cast<long>(log->scans.size())) {
    log->warnings.push_back(std::to_string(log->scans.size() - with_returns) +
                            " scans have no returns; their poses come from odometry alone");
  }
  if (reordered > 0) {
    // Stable sort by time, carrying each scan's line and odometry along.
    std::vector<size_t> order(log->scans.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return log->scans[a].timestamp < log->scans[b].timestamp;
    });
    SlamLog sorted;
    Trajectory sorted_odometry;
    for (size_t i : order) {
      sorted.scans.push_back(std::move(log->scans[i]));
      sorted.scan_lines.push_back(log->scan_lines[i]);
      sorted_odometry.push_back(laser_odometry[i]);
    }
    log->scans = std::move(sorted.scans);
    log->scan_lines = std::move(sorted.scan_lines);
    laser_odometry = std::move(sorted_odometry);
    log->warnings.push_back(std::to_string(reordered) +
                            " scans came after a newer scan in the file; processing all scans in "
                            "timestamp order");
  }
  if (out_of_order > 0) {
    log->warnings.push_back("dropped " + std::to_string(out_of_order) + " scans older than the scan before them");
  }
  if (odom_out_of_order > 0 && !Moves(laser_odometry)) {
    log->warnings.push_back("ignored " + std::to_string(odom_out_of_order) +
                            " ODOM lines older than the ODOM line before them");
  }
  if (Moves(laser_odometry)) {
    log->odometry = std::move(laser_odometry);
    log->odometry_source = "laser lines";
  } else if (!odom_lines.empty() && Moves(odom_lines)) {
    log->odometry = std::move(odom_lines);
    log->odometry_source = "ODOM lines";
  } else {
    log->odometry_source = "none";
    log->warnings.push_back(
        "the log's odometry never changes: mapping without odometry (scan matching alone, with a "
        "wider search; expect worse results in corridors)");
  }
  return true;
}

bool RunSlam(const SlamLog& log, LocalSlam* slam, SlamRunResult* result, std::string* error,
             const std::function<void(size_t, size_t)>& progress) {
  *result = SlamRunResult();
  const bool per_scan_odometry = log.odometry_source == "laser lines";
  size_t next_odometry = 0;
  const size_t total = log.scans.size();
  const size_t report_every = std::max<size_t>(1, total / 20);
  const auto start = std::chrono::steady_clock::now();
  // A few at a time: each replaces (and frees) the one it supersedes before the next is
  // rendered, so a loop closure that moves every submap does not hold two copies of the map.
  auto collect = [&]() {
    constexpr size_t kBatch = 4;
    for (std::vector<Submap> batch = slam->TakeSubmapUpdates(kBatch); !batch.empty();
         batch = slam->TakeSubmapUpdates(kBatch)) {
      for (Submap& submap : batch) {
        const int64_t id = submap.submap_id;
        result->submaps[id] = PackSubmap(std::move(submap));
      }
    }
  };
  for (size_t i = 0; i < total; ++i) {
    const LaserScan& scan = log.scans[i];
    if (per_scan_odometry) {
      if (!slam->AddOdometry(log.odometry[i], error)) return false;
    } else {
      // ODOM lines up to the scan's time; stragglers behind an earlier scan are skipped.
      while (next_odometry < log.odometry.size() && log.odometry[next_odometry].timestamp <= scan.timestamp) {
        std::string ignored;
        slam->AddOdometry(log.odometry[next_odometry++], &ignored);
      }
    }
    if (!slam->AddScan(scan, error)) {
      *error = "scan at line " + std::to_string(log.scan_lines[i]) + ": " + *error;
      return false;
    }
    // Not after every scan: each graph optimisation moves every finished submap, and each
    // collection packs those it finds moved. Every 1,024 scans (not 64) several optimisations
    // fold into one repacking: intel 24.8 -> 22.7 s, the same map and trajectory
    // (docs/BENCHMARKS.md, issue 4, session 34).
    if (i % 1024 == 0) collect();
    if (progress && (i + 1) % report_every == 0 && i + 1 < total) progress(i + 1, total);
  }
  // Every scan is in; the backend's last work (a final loop closure: ~10 s on intel with the
  // particle filters' layer) comes now.
  if (progress) progress(total, total);
  slam->Finish();
  collect();
  result->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result->trajectory = slam->trajectory();
  return true;
}

}  // namespace fleetmap

#include "shared/tools/log_summary.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <optional>

namespace fleetmap {
namespace {

// Message types come from the file: keep them printable and short (a binary file's "types" are
// arbitrary bytes).
std::string Printable(const std::string& type) {
  constexpr size_t kMaxLength = 24;
  std::string out;
  for (char c : type.substr(0, kMaxLength)) {
    out += (c >= 0x21 && c <= 0x7e) ? c : '?';
  }
  return type.size() > kMaxLength ? out + "..." : out;
}

void Stamp(double timestamp, LogSummary* summary, bool* first) {
  if (*first) {
    summary->first_timestamp = timestamp;
    *first = false;
  }
  summary->last_timestamp = timestamp;
}

}  // namespace

bool SummarizeLog(const std::string& path, const CarmenReaderOptions& options, LogSummary* summary,
                  std::string* error, const std::function<void(long scans)>& progress,
                  long progress_every) {
  std::unique_ptr<CarmenReader> reader = CarmenReader::Open(path, options, error);
  if (!reader) return false;
  *summary = LogSummary();
  summary->path = path;
  bool first_stamp = true;
  std::optional<Rigid2d> last_laser_pose;
  std::optional<Rigid2d> last_odom_pose;
  CarmenRecord record;
  while (reader->Next(&record)) {
    if (const auto* laser = std::get_if<LaserRecord>(&record)) {
      const LaserScan& scan = laser->scan;
      if (summary->laser_scans == 0) summary->first_sensor_in_robot = scan.sensor_in_robot;
      ++summary->laser_scans;
      ++summary->beams_per_scan[scan.size()];
      summary->readings += scan.size();
      for (float range : scan.ranges) {
        if (std::isfinite(range)) {
          summary->max_return_range = std::max(summary->max_return_range, range);
        } else {
          ++summary->no_return_readings;
        }
      }
      if (last_laser_pose) {
        summary->laser_odometry_distance +=
            (laser->robot_pose.translation() - last_laser_pose->translation()).norm();
      }
      last_laser_pose = laser->robot_pose;
      Stamp(scan.timestamp, summary, &first_stamp);
      if (progress && progress_every > 0 && summary->laser_scans % progress_every == 0) {
        progress(summary->laser_scans);
      }
    } else if (const auto* odometry = std::get_if<OdometryRecord>(&record)) {
      ++summary->odometry_records;
      if (last_odom_pose) {
        summary->odom_distance +=
            (odometry->robot_pose.translation() - last_odom_pose->translation()).norm();
      }
      last_odom_pose = odometry->robot_pose;
      Stamp(odometry->timestamp, summary, &first_stamp);
    } else if (const auto* param = std::get_if<ParamRecord>(&record)) {
      summary->params.emplace_back(param->name, param->value);
    }
  }
  summary->lines = reader->line_number();
  summary->skipped_lines = reader->skipped_lines();
  summary->first_skipped_error = reader->first_skipped_error();
  summary->message_counts = reader->message_counts();
  if (!reader->error().empty()) {
    if (error) *error = reader->error();
    return false;
  }
  return true;
}

void PrintLogSummary(const LogSummary& s, int max_params, std::ostream& out) {
  out << std::fixed;
  out << "log: " << s.path << "\n";
  out << "lines: " << s.lines << ", skipped bad lines: " << s.skipped_lines << "\n";
  if (s.skipped_lines > 0) out << "  first skipped: " << s.first_skipped_error << "\n";
  // The most frequent message types first; a garbage file can have dozens.
  std::vector<std::pair<std::string, long>> counts(s.message_counts.begin(),
                                                   s.message_counts.end());
  std::stable_sort(counts.begin(), counts.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  constexpr size_t kMaxTypesShown = 12;
  out << "messages:";
  long others = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    if (i >= kMaxTypesShown) {
      others += counts[i].second;
      continue;
    }
    const std::string& type = counts[i].first;
    out << " " << (type == "#" ? std::string("comments") : Printable(type)) << "="
        << counts[i].second;
  }
  if (others > 0) out << " (other types)=" << others;
  out << "\n";
  out << "laser scans: " << s.laser_scans << "\n";
  for (const auto& [beams, count] : s.beams_per_scan) {
    out << "  " << beams << " beams: " << count << " scans\n";
  }
  if (s.readings > 0) {
    out << std::setprecision(1) << "  no-return readings: " << s.no_return_readings << " ("
        << 100.0 * static_cast<double>(s.no_return_readings) / static_cast<double>(s.readings)
        << "%), longest return " << std::setprecision(2) << s.max_return_range << " m\n";
  }
  out << std::setprecision(3)
      << "  laser mount (sensor_in_robot, first scan): " << s.first_sensor_in_robot << "\n";
  out << "odometry records: " << s.odometry_records << "\n";
  out << std::setprecision(6) << "time span: " << s.first_timestamp << " .. " << s.last_timestamp
      << " (" << std::setprecision(1) << s.last_timestamp - s.first_timestamp << " s)\n";
  out << std::setprecision(1) << "distance travelled (raw odometry): " << s.laser_odometry_distance
      << " m over laser scans";
  if (s.odometry_records > 0) out << ", " << s.odom_distance << " m over ODOM";
  out << "\n";
  out << "params: " << s.params.size() << "\n";
  const size_t shown =
      max_params < 0 ? s.params.size() : std::min(s.params.size(), static_cast<size_t>(max_params));
  for (size_t i = 0; i < shown; ++i) {
    out << "  " << s.params[i].first << " = " << s.params[i].second << "\n";
  }
  if (shown < s.params.size()) {
    out << "  ... " << s.params.size() - shown << " more (--all-params)\n";
  }
}

}  // namespace fleetmap

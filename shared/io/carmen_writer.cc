#include "shared/io/carmen_writer.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "shared/io/carmen_parse.h"

namespace fleetmap {
namespace {

// Written for no-return beams when a scan has no finite range_max: the SICK overflow code.
constexpr float kOverflowRange = 81.91f;

void AppendFixed(double value, std::string* line) {
  char buffer[64];
  const int n = std::snprintf(buffer, sizeof(buffer), " %.6f", value);
  line->append(buffer, static_cast<size_t>(n > 0 ? n : 0));
}

// Shortest text that reads back to the same float, so ranges round-trip exactly.
void AppendRange(float value, std::string* line) {
  char buffer[32];
  buffer[0] = ' ';
  const auto result = std::to_chars(buffer + 1, buffer + sizeof(buffer), value);
  line->append(buffer, static_cast<size_t>(result.ptr - buffer));
}

void AppendPose(const Rigid2d& pose, std::string* line) {
  AppendFixed(pose.x(), line);
  AppendFixed(pose.y(), line);
  AppendFixed(pose.rotation(), line);
}

// CARMEN fields are whitespace separated, so names and values must not contain line breaks.
std::string OneLine(std::string text, char replacement) {
  for (char& c : text) {
    if (c == '\n' || c == '\r' || (replacement == '_' && (c == ' ' || c == '\t'))) {
      c = replacement;
    }
  }
  return text.empty() ? std::string("-") : text;
}

bool IsFlaserGeometry(const LaserScan& scan) {
  return std::abs(scan.angle_min - carmen::kFlaserAngleMin) < 1e-6 &&
         std::abs(scan.angle_increment - carmen::FlaserAngleIncrement(scan.size())) < 1e-6;
}

}  // namespace

CarmenWriter::CarmenWriter(const std::string& path, const std::string& hostname)
    : out_(path), hostname_(OneLine(hostname, '_')) {
  out_ << "# CARMEN log written by fleetmap\n"
       << "# FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname "
          "logger_timestamp\n";
}

void CarmenWriter::WriteParam(const std::string& name, const std::string& value, double timestamp) {
  if (first_timestamp_ < 0.0) first_timestamp_ = timestamp;
  std::string line = "PARAM " + OneLine(name, '_') + " " + OneLine(value, ' ');
  AppendFixed(timestamp, &line);
  line += " " + hostname_;
  AppendFixed(timestamp - first_timestamp_, &line);
  out_ << line << '\n';
}

void CarmenWriter::WriteOdometry(const OdometryRecord& odometry) {
  if (first_timestamp_ < 0.0) first_timestamp_ = odometry.timestamp;
  std::string line = "ODOM";
  AppendPose(odometry.robot_pose, &line);
  AppendFixed(odometry.translational_velocity, &line);
  AppendFixed(odometry.rotational_velocity, &line);
  AppendFixed(0.0, &line);  // acceleration
  AppendFixed(odometry.timestamp, &line);
  line += " " + hostname_;
  AppendFixed(odometry.timestamp - first_timestamp_, &line);
  out_ << line << '\n';
}

// The reader turns readings at or above its max range into no-returns; a PARAM
// robot_front_laser_max before the scan tells it this scan's range_max, so the no-returns
// (written as range_max) and every real return read back as they were.
void CarmenWriter::WriteLaser(const LaserRecord& laser) {
  const LaserScan& scan = laser.scan;
  if (first_timestamp_ < 0.0) first_timestamp_ = scan.timestamp;
  const bool finite_max = std::isfinite(scan.range_max) && scan.range_max > 0.0f;
  const float no_return = finite_max ? scan.range_max : kOverflowRange;
  if (no_return != written_max_range_) {
    char value[32];
    const auto result = std::to_chars(value, value + sizeof(value), no_return);
    WriteParam("robot_front_laser_max", std::string(value, result.ptr), scan.timestamp);
    written_max_range_ = no_return;
  }
  const bool flaser = IsFlaserGeometry(scan);
  const Rigid2d laser_pose = laser.robot_pose * scan.sensor_in_robot;
  std::string line;
  line.reserve(static_cast<size_t>(scan.size()) * 8 + 256);
  if (flaser) {
    line = "FLASER " + std::to_string(scan.size());
  } else {
    line = "ROBOTLASER1 0";
    AppendFixed(scan.angle_min, &line);
    AppendFixed(static_cast<double>(scan.angle_increment) * std::max(scan.size() - 1, 0), &line);
    AppendFixed(scan.angle_increment, &line);
    AppendFixed(no_return, &line);
    line += " 0.010000 0 " + std::to_string(scan.size());
  }
  for (float range : scan.ranges) AppendRange(std::isfinite(range) ? range : no_return, &line);
  if (!flaser) line += " 0";  // no remission values
  AppendPose(laser_pose, &line);
  AppendPose(laser.robot_pose, &line);
  if (!flaser) line += " 0.000000 0.000000 0.000000 0.000000 0.000000";
  AppendFixed(scan.timestamp, &line);
  line += " " + hostname_;
  const double logger =
      laser.logger_timestamp != 0.0 ? laser.logger_timestamp : scan.timestamp - first_timestamp_;
  AppendFixed(logger, &line);
  out_ << line << '\n';
}

bool CarmenWriter::Close() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  return ok && static_cast<bool>(out_);
}

}  // namespace fleetmap

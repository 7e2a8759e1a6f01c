#include "shared/io/carmen_parse.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "shared/io/carmen_field_reader.h"

namespace fleetmap {
namespace carmen {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

bool Finish(const FieldReader& reader, std::string* error) {
  if (error) *error = reader.error();
  return false;
}

// The robot-to-laser mount: from the two poses when they differ, else from the log's
// robot_frontlaser_offset PARAM (old logs print the robot pose twice).
void SetMount(const double laser_raw[3], const double robot_raw[3], const LogState& state,
              LaserRecord* record) {
  const bool same =
      laser_raw[0] == robot_raw[0] && laser_raw[1] == robot_raw[1] && laser_raw[2] == robot_raw[2];
  if (!same) {
    record->scan.sensor_in_robot = record->robot_pose.inverse() * record->laser_pose;
  } else if (state.has_frontlaser_offset) {
    record->scan.sensor_in_robot = Rigid2d(state.frontlaser_offset, 0.0, 0.0);
    record->laser_pose = record->robot_pose * record->scan.sensor_in_robot;
  } else {
    record->scan.sensor_in_robot = Rigid2d();
  }
}

// The fields every message ends with: ipc_timestamp ipc_hostname logger_timestamp.
bool ReadTrailer(FieldReader* reader, double* ipc_timestamp, double* logger_timestamp) {
  if (!reader->FiniteDouble("ipc_timestamp", ipc_timestamp)) return false;
  if (!reader->Skip(1, "ipc_hostname")) return false;  // any text
  return reader->FiniteDouble("logger_timestamp", logger_timestamp);
}

}  // namespace

void SplitTokens(std::string_view line, Tokens* tokens) {
  tokens->clear();
  const char* p = line.data();
  const char* end = p + line.size();
  while (p < end) {
    while (p < end && IsSpace(*p)) ++p;
    const char* start = p;
    while (p < end && !IsSpace(*p)) ++p;
    if (p > start) tokens->emplace_back(start, static_cast<size_t>(p - start));
  }
}

bool ParseDouble(std::string_view token, double* value) {
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last) return false;
  const auto [ptr, ec] = std::from_chars(first, last, *value);
  return ec == std::errc() && ptr == last;
}

bool ParseInt(std::string_view token, long* value) {
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last) return false;
  const auto [ptr, ec] = std::from_chars(first, last, *value);
  return ec == std::errc() && ptr == last;
}

double FlaserAngleIncrement(int beams) {
  const int intervals = beams % 2 == 1 ? beams - 1 : beams;
  return intervals > 0 ? M_PI / intervals : 0.0;
}

// ODOM x y theta tv rv accel ipc_timestamp ipc_hostname logger_timestamp
bool ParseOdometry(const Tokens& tokens, OdometryRecord* record, std::string* error) {
  FieldReader reader(tokens, "ODOM");
  double raw[3];
  double accel;
  double logger_timestamp;
  if (!reader.Expect(9, "x y theta tv rv accel ipc_timestamp ipc_hostname logger_timestamp") ||
      !reader.Pose("pose", &record->robot_pose, raw) ||
      !reader.Double("tv", &record->translational_velocity) ||
      !reader.Double("rv", &record->rotational_velocity) || !reader.Double("accel", &accel) ||
      !ReadTrailer(&reader, &record->timestamp, &logger_timestamp)) {
    return Finish(reader, error);
  }
  return true;
}

// FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname
// logger_timestamp
bool ParseFlaser(const Tokens& tokens, const LogState& state, int max_beams, LaserRecord* record,
                 std::string* error) {
  FieldReader reader(tokens, "FLASER");
  long beams = 0;
  if (!reader.Count("beam count", max_beams, &beams)) {
    return Finish(reader, error);
  }
  const size_t left = reader.left();
  if (left != static_cast<size_t>(beams) + 9) {
    const long found_ranges = static_cast<long>(left) - 9;
    reader.Fail("expected " + std::to_string(beams) + " ranges and 9 pose/time fields, found " +
                (found_ranges >= 0 ? std::to_string(found_ranges) + " ranges"
                                   : std::to_string(left) + " values in all"));
    return Finish(reader, error);
  }
  std::vector<float> ranges;
  double laser_raw[3];
  double robot_raw[3];
  if (!reader.Ranges(beams, &ranges) ||
      !reader.Pose("laser pose", &record->laser_pose, laser_raw) ||
      !reader.Pose("robot pose", &record->robot_pose, robot_raw) ||
      !ReadTrailer(&reader, &record->scan.timestamp, &record->logger_timestamp)) {
    return Finish(reader, error);
  }
  const double timestamp = record->scan.timestamp;
  record->scan = MakeLaserScan(timestamp, static_cast<float>(kFlaserAngleMin),
                               static_cast<float>(FlaserAngleIncrement(static_cast<int>(beams))),
                               0.0f, static_cast<float>(state.max_range), ranges);
  SetMount(laser_raw, robot_raw, state, record);
  return true;
}

namespace {

// The seven fields before a ROBOTLASER1 beam count.
struct RobotLaserHeader {
  double start_angle = 0.0;
  double fov = 0.0;
  double angular_res = 0.0;
  double max_range = 0.0;
};

bool ReadRobotLaserHeader(FieldReader* reader, RobotLaserHeader* header) {
  double ignored;
  if (!reader->Double("laser_type", &ignored) ||
      !reader->FiniteDouble("start_angle", &header->start_angle) ||
      !reader->FiniteDouble("fov", &header->fov) ||
      !reader->FiniteDouble("angular_res", &header->angular_res) ||
      !reader->Double("max_range", &header->max_range) || !reader->Double("accuracy", &ignored)) {
    return false;
  }
  return reader->Double("remission_mode", &ignored);
}

// After the remissions: laser pose, robot pose, five motion fields, the trailer.
bool ReadRobotLaserTail(FieldReader* reader, double laser_raw[3], double robot_raw[3],
                        LaserRecord* record) {
  if (!reader->Pose("laser pose", &record->laser_pose, laser_raw) ||
      !reader->Pose("robot pose", &record->robot_pose, robot_raw)) {
    return false;
  }
  double ignored;
  for (const char* name :
       {"laser_tv", "laser_rv", "forward_safety_dist", "side_safety_dist", "turn_axis"}) {
    if (!reader->Double(name, &ignored)) return false;
  }
  return ReadTrailer(reader, &record->scan.timestamp, &record->logger_timestamp);
}

}  // namespace

// ROBOTLASER1 laser_type start_angle fov angular_res max_range accuracy remission_mode
// n r_1..r_n m rem_1..rem_m laser_x laser_y laser_theta robot_x robot_y robot_theta laser_tv
// laser_rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp ipc_hostname
// logger_timestamp
bool ParseRobotLaser(const Tokens& tokens, const LogState& state, int max_beams,
                     LaserRecord* record, std::string* error) {
  FieldReader reader(tokens, "ROBOTLASER1");
  constexpr size_t kTail = 6 + 5 + 3;
  RobotLaserHeader header;
  long beams = 0;
  if (!ReadRobotLaserHeader(&reader, &header) || !reader.Count("beam count", max_beams, &beams)) {
    return Finish(reader, error);
  }
  if (reader.left() < static_cast<size_t>(beams) + 1 + kTail) {
    reader.Fail("expected " + std::to_string(beams) + " ranges, a remission count and " +
                std::to_string(kTail) + " pose/time fields, found only " +
                std::to_string(reader.left()) + " values");
    return Finish(reader, error);
  }
  std::vector<float> ranges;
  long remissions = 0;
  double laser_raw[3];
  double robot_raw[3];
  if (!reader.Ranges(beams, &ranges) || !reader.Count("remission count", max_beams, &remissions) ||
      !reader.Expect(static_cast<size_t>(remissions) + kTail,
                     std::to_string(remissions) + " remissions and " + std::to_string(kTail) +
                         " pose/time fields") ||
      !reader.Skip(remissions, "remissions") ||
      !ReadRobotLaserTail(&reader, laser_raw, robot_raw, record)) {
    return Finish(reader, error);
  }
  double increment = header.angular_res;
  if (increment == 0.0 && beams > 1) increment = header.fov / static_cast<double>(beams - 1);
  double max_range = state.max_range;
  if (std::isfinite(header.max_range) && header.max_range > 0.0) {
    max_range = std::min(max_range, header.max_range);
  }
  const double timestamp = record->scan.timestamp;
  record->scan =
      MakeLaserScan(timestamp, static_cast<float>(header.start_angle),
                    static_cast<float>(increment), 0.0f, static_cast<float>(max_range), ranges);
  // ROBOTLASER1 always carries the true laser pose; no PARAM fallback.
  LogState no_param = state;
  no_param.has_frontlaser_offset = false;
  SetMount(laser_raw, robot_raw, no_param, record);
  return true;
}

// PARAM name value [[ipc_timestamp] ipc_hostname logger_timestamp]. A value may hold spaces
// (file paths); everything between the name and the trailer is the value.
bool ParseParam(const Tokens& tokens, ParamRecord* record, std::string* error) {
  if (tokens.size() < 3) {
    if (error) *error = "PARAM: expected a name and a value";
    return false;
  }
  // The trailer is "ipc_timestamp hostname logger_timestamp" in newer logs and just
  // "hostname logger_timestamp" in old ones (intel, aces).
  const size_t n = tokens.size();
  size_t value_end = n;
  double number;
  if (n >= 5 && ParseDouble(tokens[n - 1], &number) && !ParseDouble(tokens[n - 2], &number)) {
    value_end = n >= 6 && ParseDouble(tokens[n - 3], &number) ? n - 3 : n - 2;
  }
  record->name = std::string(tokens[1]);
  record->value.clear();
  for (size_t i = 2; i < value_end; ++i) {
    if (i > 2) record->value += ' ';
    record->value += tokens[i];
  }
  return true;
}

}  // namespace carmen
}  // namespace fleetmap

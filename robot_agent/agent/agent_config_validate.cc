// The checks on a loaded configuration, each naming the field it refuses.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "robot_agent/agent/agent_config.h"
#include "robot_agent/agent/slam_factory.h"

namespace fleetmap {
namespace {

class Checker {
 public:
  explicit Checker(std::string* error) : error_(error) {}
  bool ok() const { return error_->empty(); }

  void Fail(const std::string& field, const std::string& message) {
    if (ok()) *error_ = field + ": " + message;
  }
  template <typename T>
  void Positive(const std::string& field, T value) {
    if (!(value > 0) || !std::isfinite(static_cast<double>(value))) {
      Fail(field, "must be > 0, got " + Format(value));
    }
  }
  template <typename T>
  void NonNegative(const std::string& field, T value) {
    if (!(value >= 0) || !std::isfinite(static_cast<double>(value))) {
      Fail(field, "must be >= 0, got " + Format(value));
    }
  }
  void Backoff(const std::string& field, const BackoffOptions& backoff) {
    Positive(field + ".initial", backoff.initial);
    if (!(backoff.multiplier >= 1.0) || !std::isfinite(backoff.multiplier)) {
      Fail(field + ".multiplier", "must be >= 1, got " + Format(backoff.multiplier));
    }
    Positive(field + ".max", backoff.max);
    if (ok() && backoff.max < backoff.initial) {
      Fail(field + ".max",
           "must be >= initial (" + Format(backoff.initial) + "), got " + Format(backoff.max));
    }
    if (!(backoff.jitter >= 0.0 && backoff.jitter <= 1.0)) {
      Fail(field + ".jitter", "must be in [0, 1], got " + Format(backoff.jitter));
    }
  }
  void FileExists(const std::string& field, const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) Fail(field, "no such file: " + path);
  }

 private:
  template <typename T>
  static std::string Format(T value) {
    std::ostringstream out;
    out << value;
    return out.str();
  }
  std::string* error_;
};

bool IsValidRobotId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

// Only checked when detection is enabled: a disabled section may hold anything parseable.
void ValidateDetection(const AgentConfig& config, Checker& check) {
  const DetectionConfig& detection = config.detection;
  if (!detection.enabled) return;
  const bool simulator = config.source.type == SourceConfig::Type::kSimulator;
  if (simulator && !config.source.sim_camera) {
    check.Fail("detection.enabled", "needs camera frames: set source.simulator.camera: true");
  }
  if (!simulator && config.source.camera_index.empty()) {
    check.Fail("detection.enabled", "needs camera frames: set source.carmen.camera_frames");
  }
  if (!detection.colour_model.empty() && !detection.marker_hues.empty()) {
    check.Fail("detection.colour_model", "give either colour_model or marker_hues, not both");
  }
  if (!simulator && detection.colour_model.empty() && detection.marker_hues.empty()) {
    check.Fail("detection", "a log needs marker colours: colour_model (a file from "
                            "fleetmap-detect-calibrate) or marker_hues {robot_id: hue_degrees}");
  }
  if (!detection.colour_model.empty()) {
    check.FileExists("detection.colour_model", detection.colour_model);
  }
  for (const auto& [robot, hue] : detection.marker_hues) {
    if (!IsValidRobotId(robot)) check.Fail("detection.marker_hues", "bad robot id '" + robot + "'");
    if (!(hue >= 0.0 && hue < 360.0)) {
      check.Fail("detection.marker_hues." + robot, "must be in [0, 360) degrees");
    }
  }
  if (!(detection.hue_half_width > 0.0 && detection.hue_half_width <= 90.0)) {
    check.Fail("detection.hue_half_width", "must be in (0, 90] degrees");
  }
  if (!(detection.min_saturation >= 0.0 && detection.min_saturation < 1.0)) {
    check.Fail("detection.min_saturation", "must be in [0, 1)");
  }
  if (detection.learn_views < 1 || detection.learn_views > 1000) {
    check.Fail("detection.learn_views", "must be in [1, 1000]");
  }
  std::string why;
  if (!simulator && !detection.camera.IsValid(&why)) check.Fail("detection.camera", why);
  if (!simulator && !detection.marker.IsValid(&why)) check.Fail("detection.marker", why);
  check.Positive("detection.laser_range_noise", detection.laser_range_noise);
  check.Positive("detection.max_time_difference", detection.max_time_difference);
  for (const auto& [marker, robot] : detection.robot_ids) {
    if (!IsValidRobotId(robot)) {
      check.Fail("detection.robot_ids." + marker,
                 "must be 1-64 characters of [A-Za-z0-9_.-], got '" + robot + "'");
    }
  }
}

void ValidateLocalization(const AgentConfig& config, Checker& check) {
  const LocalizationConfig& localization = config.localization;
  if (!localization.enabled) return;
  if (localization.map.empty()) {
    if (!config.map.subscribe) {
      check.Fail("localization.map",
                 "missing, and map.subscribe is false: give a map file or follow the server's map");
    }
    // The server's map is in the global frame: nothing to place.
    if (config.start_pose) {
      check.Fail("robot.start_pose",
                 "must be left out when localizing in the server's global map (its frame is the "
                 "global one); it places a map file in the global frame");
    }
  } else {
    check.FileExists("localization.map", localization.map);
  }
  check.Positive("localization.map_wait", localization.map_wait);
  if (localization.initial_pose && !localization.initial_pose->IsFinite()) {
    check.Fail("localization.initial_pose", "must be finite numbers");
  }
  check.Positive("localization.initial_position_std", localization.initial_position_std);
  check.Positive("localization.initial_heading_std", localization.initial_heading_std);
  if (localization.particles < 10 || localization.particles > 1000000) {
    check.Fail("localization.particles",
               "must be in [10, 1000000], got " + std::to_string(localization.particles));
  }
  if (localization.beams < 1 || localization.beams > 10000) {
    check.Fail("localization.beams",
               "must be in [1, 10000], got " + std::to_string(localization.beams));
  }
  check.NonNegative("localization.seed", localization.seed);
}

}  // namespace

bool ValidateAgentConfig(const AgentConfig& config, std::string* error) {
  error->clear();
  Checker check(error);
  if (config.robot_id.empty()) {
    check.Fail("robot.id", "missing");
  } else if (!IsValidRobotId(config.robot_id)) {
    check.Fail("robot.id",
               "must be 1-64 characters of [A-Za-z0-9_.-], got '" + config.robot_id + "'");
  }
  if (config.start_pose && !config.start_pose->IsFinite()) {
    check.Fail("robot.start_pose", "must be finite numbers");
  }
  if (config.server_address.empty())
    check.Fail("server.address", "missing (host:port)");
  else if (config.server_address.find(':') == std::string::npos) {
    check.Fail("server.address", "must be host:port, got '" + config.server_address + "'");
  }
  if (config.outbox_path.empty()) check.Fail("outbox.path", "missing (an SQLite file)");
  const SlamConfig& slam = config.slam;
  const std::vector<std::string> algorithms = AvailableSlamAlgorithms();
  if (std::find(algorithms.begin(), algorithms.end(), slam.algorithm) == algorithms.end()) {
    std::string known;
    for (const std::string& name : algorithms) known += (known.empty() ? "" : ", ") + name;
    check.Fail("slam.algorithm", "'" + slam.algorithm +
                                     "' is not available in this build (available: " + known + ")");
  }
  check.Positive("slam.resolution", slam.resolution);
  check.Positive("slam.max_range", slam.max_range);
  check.NonNegative("slam.submap_scans", slam.submap_scans);
  check.NonNegative("slam.submap_travel", slam.submap_travel);
  if (check.ok() && slam.submap_scans == 0 && slam.submap_travel == 0.0) {
    check.Fail("slam.submap_scans", "and slam.submap_travel are both 0: submaps would never end");
  }
  check.NonNegative("slam.min_translation", slam.min_translation);
  check.NonNegative("slam.min_rotation", slam.min_rotation);
  const SourceConfig& source = config.source;
  if (source.type == SourceConfig::Type::kCarmen) {
    if (source.log_path.empty())
      check.Fail("source.carmen.log", "missing (a CARMEN log file)");
    else
      check.FileExists("source.carmen.log", source.log_path);
    if (!source.camera_index.empty()) {
      check.FileExists("source.carmen.camera_frames", source.camera_index);
    }
  } else {
    if (source.scenario.empty()) check.Fail("source.simulator.scenario", "missing");
    if (source.sim_robot.empty()) check.Fail("source.simulator.robot", "missing");
  }
  check.NonNegative("source.speed", source.speed);
  const UploadConfig& upload = config.upload;
  if (upload.uploader.max_batch_items < 1 || upload.uploader.max_batch_items > 256) {
    check.Fail("upload.batch_size",
               "must be in [1, 256], got " + std::to_string(upload.uploader.max_batch_items));
  }
  check.Positive("upload.max_batch_bytes", upload.uploader.max_batch_bytes);
  check.Positive("upload.rpc_timeout", upload.uploader.rpc_timeout);
  check.Backoff("upload.backoff", upload.uploader.backoff);
  check.NonNegative("upload.trajectory_period", upload.trajectory_period);
  check.NonNegative("upload.active_submap_period", upload.active_submap_period);
  check.NonNegative("upload.drain_timeout", upload.drain_timeout);
  check.NonNegative("upload.flush_timeout", upload.flush_timeout);
  check.Backoff("map.reconnect", config.map.reconnect);
  ValidateDetection(config, check);
  ValidateLocalization(config, check);
  check.NonNegative("status.period", config.status_period);
  return check.ok();
}

}  // namespace fleetmap

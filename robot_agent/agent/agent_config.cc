#include "robot_agent/agent/agent_config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

namespace fleetmap {
namespace {

// Reads the fields of one YAML map, remembering the first problem and which keys were used so
// that unknown keys (typos) can be refused.
class Fields {
 public:
  Fields(const YAML::Node& node, std::string path, std::string* problem)
      : node_(node), path_(std::move(path)), problem_(problem) {
    if (node_ && !node_.IsNull() && !node_.IsMap()) Fail(path_, "must be a map");
  }

  std::string Path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  bool Has(const std::string& key) const { return node_.IsMap() && node_[key]; }
  YAML::Node Child(const std::string& key) {
    used_.insert(key);
    return node_.IsMap() ? node_[key] : YAML::Node();
  }

  template <typename T>
  void Get(const std::string& key, T* value) {
    const YAML::Node child = Child(key);
    if (!child || child.IsNull()) return;
    try {
      if (!child.IsScalar()) throw YAML::Exception(YAML::Mark(), "");
      *value = child.as<T>();
    } catch (const YAML::Exception&) {
      Fail(Path(key), std::string("must be a ") + TypeName<T>() + ", got '" + Dump(child) + "'");
    }
  }

  // Refuses keys that were never read.
  void CheckUnknown() {
    if (!node_.IsMap()) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.as<std::string>();
      if (!used_.count(key)) Fail(Path(key), "unknown field (misspelt?)");
    }
  }

  void Fail(const std::string& field, const std::string& message) {
    if (problem_->empty()) *problem_ = field + ": " + message;
  }

 private:
  template <typename T>
  static const char* TypeName() {
    if constexpr (std::is_same_v<T, bool>) return "boolean (true/false)";
    if constexpr (std::is_same_v<T, int>) return "whole number";
    if constexpr (std::is_same_v<T, double>) return "number";
    return "string";
  }
  static std::string Dump(const YAML::Node& node) {
    std::ostringstream out;
    out << node;
    return out.str();
  }

  YAML::Node node_;
  std::string path_;
  std::string* problem_;
  std::set<std::string> used_;
};

std::string Resolve(const std::string& base_dir, const std::string& path) {
  if (path.empty() || base_dir.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(base_dir) / path).lexically_normal().string();
}

void ReadBackoff(Fields& parent, const std::string& key, BackoffOptions* backoff,
                 std::string* problem) {
  Fields fields(parent.Child(key), parent.Path(key), problem);
  fields.Get("initial", &backoff->initial);
  fields.Get("multiplier", &backoff->multiplier);
  fields.Get("max", &backoff->max);
  fields.Get("jitter", &backoff->jitter);
  fields.CheckUnknown();
}

void ReadSpeed(Fields& source, SourceConfig* config) {
  std::string text;
  source.Get("speed", &text);
  if (text.empty() || text == "max" || text == "fast") {
    config->speed = 0.0;
  } else if (text == "realtime" || text == "real-time" || text == "real_time") {
    config->speed = 1.0;
  } else {
    char* end = nullptr;
    config->speed = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(config->speed) ||
        config->speed <= 0.0) {
      source.Fail(
          source.Path("speed"),
          "must be 'max', 'realtime' or a factor > 0 (2 = twice real time), got '" + text + "'");
    }
  }
}

void ReadSource(Fields& root, const std::string& base_dir, SourceConfig* config,
                std::string* problem) {
  Fields source(root.Child("source"), "source", problem);
  if (!root.Has("source")) source.Fail("source", "missing (carmen: or simulator:)");
  const bool carmen = source.Has("carmen");
  const bool simulator = source.Has("simulator");
  if (carmen == simulator && root.Has("source")) {
    source.Fail("source", "give exactly one of 'carmen' and 'simulator'");
  }
  Fields log(source.Child("carmen"), "source.carmen", problem);
  log.Get("log", &config->log_path);
  log.Get("camera_frames", &config->camera_index);
  log.CheckUnknown();
  Fields sim(source.Child("simulator"), "source.simulator", problem);
  sim.Get("scenario", &config->scenario);
  sim.Get("robot", &config->sim_robot);
  sim.Get("camera", &config->sim_camera);
  sim.CheckUnknown();
  ReadSpeed(source, config);
  source.CheckUnknown();
  config->type = simulator ? SourceConfig::Type::kSimulator : SourceConfig::Type::kCarmen;
  config->log_path = Resolve(base_dir, config->log_path);
  config->camera_index = Resolve(base_dir, config->camera_index);
  // A scenario is a file (relative to the config) or a shipped scenario's name.
  const std::string scenario_file = Resolve(base_dir, config->scenario);
  if (!config->scenario.empty() && std::filesystem::exists(scenario_file)) {
    config->scenario = scenario_file;
  }
}

// {x:, y:, theta:}, all three required.
void ReadPose(Fields& parent, const std::string& key, std::optional<Rigid2d>* value,
              std::string* problem) {
  if (!parent.Has(key)) return;
  Fields pose(parent.Child(key), parent.Path(key), problem);
  double x = 0.0, y = 0.0, theta = 0.0;
  for (const char* axis : {"x", "y", "theta"}) {
    if (!pose.Has(axis)) pose.Fail(pose.Path(axis), "missing (" + key + " needs x, y, theta)");
  }
  pose.Get("x", &x);
  pose.Get("y", &y);
  pose.Get("theta", &theta);
  pose.CheckUnknown();
  *value = Rigid2d(x, y, theta);
}

void ReadRobot(Fields& root, AgentConfig* config, std::string* problem) {
  Fields robot(root.Child("robot"), "robot", problem);
  robot.Get("id", &config->robot_id);
  robot.Get("name", &config->robot_name);
  ReadPose(robot, "start_pose", &config->start_pose, problem);
  robot.CheckUnknown();
}

void ReadLocalization(Fields& root, const std::string& base_dir, LocalizationConfig* config,
                      std::string* problem) {
  Fields localization(root.Child("localization"), "localization", problem);
  localization.Get("enabled", &config->enabled);
  localization.Get("map", &config->map);
  config->map = Resolve(base_dir, config->map);
  localization.Get("map_wait", &config->map_wait);
  ReadPose(localization, "initial_pose", &config->initial_pose, problem);
  localization.Get("initial_position_std", &config->initial_position_std);
  localization.Get("initial_heading_std", &config->initial_heading_std);
  localization.Get("particles", &config->particles);
  localization.Get("beams", &config->beams);
  localization.Get("seed", &config->seed);
  localization.Get("scan_seeding", &config->scan_seeding);
  localization.Get("random_injection", &config->random_injection);
  localization.Get("share_detections", &config->share_detections);
  localization.CheckUnknown();
}

void ReadUpload(Fields& root, UploadConfig* config, std::string* problem) {
  Fields upload(root.Child("upload"), "upload", problem);
  UploaderOptions& uploader = config->uploader;
  upload.Get("batch_size", &uploader.max_batch_items);
  double max_batch_bytes = static_cast<double>(uploader.max_batch_bytes);
  upload.Get("max_batch_bytes", &max_batch_bytes);
  uploader.max_batch_bytes = static_cast<int64_t>(max_batch_bytes);
  upload.Get("rpc_timeout", &uploader.rpc_timeout);
  ReadBackoff(upload, "backoff", &uploader.backoff, problem);
  upload.Get("trajectory_period", &config->trajectory_period);
  upload.Get("active_submap_period", &config->active_submap_period);
  upload.Get("drain_timeout", &config->drain_timeout);
  upload.Get("flush_timeout", &config->flush_timeout);
  upload.CheckUnknown();
}

// A map of names to scalars, e.g. marker_hues: {robot1: 120, robot2: 220}.
template <typename T>
void ReadNameMap(Fields& parent, const std::string& key, std::map<std::string, T>* values) {
  const YAML::Node node = parent.Child(key);
  if (!node || node.IsNull()) return;
  if (!node.IsMap()) return parent.Fail(parent.Path(key), "must be a map of name: value");
  for (const auto& entry : node) {
    const std::string name = entry.first.as<std::string>();
    try {
      (*values)[name] = entry.second.as<T>();
    } catch (const YAML::Exception&) {
      parent.Fail(parent.Path(key) + "." + name, "bad value");
    }
  }
}

void ReadDetection(Fields& root, const std::string& base_dir, DetectionConfig* config,
                   std::string* problem) {
  Fields detection(root.Child("detection"), "detection", problem);
  detection.Get("enabled", &config->enabled);
  detection.Get("colour_model", &config->colour_model);
  config->colour_model = Resolve(base_dir, config->colour_model);
  ReadNameMap(detection, "marker_hues", &config->marker_hues);
  detection.Get("hue_half_width", &config->hue_half_width);
  detection.Get("min_saturation", &config->min_saturation);
  detection.Get("learn_views", &config->learn_views);
  Fields camera(detection.Child("camera"), "detection.camera", problem);
  CameraModel& c = config->camera;
  camera.Get("width", &c.width);
  camera.Get("height", &c.height);
  for (auto [key, value] : {std::pair{"fx", &c.fx}, {"fy", &c.fy}, {"cx", &c.cx}, {"cy", &c.cy},
                            {"mount_height", &c.mount_height}}) {
    camera.Get(key, value);
  }
  Fields mount(camera.Child("mount"), "detection.camera.mount", problem);
  double x = 0.0, y = 0.0, theta = 0.0;
  mount.Get("x", &x);
  mount.Get("y", &y);
  mount.Get("theta", &theta);
  mount.CheckUnknown();
  c.camera_in_robot = Rigid2d(x, y, theta);
  camera.CheckUnknown();
  Fields marker(detection.Child("marker"), "detection.marker", problem);
  marker.Get("radius", &config->marker.marker_radius);
  marker.Get("bottom", &config->marker.marker_bottom);
  marker.Get("top", &config->marker.marker_top);
  marker.Get("body_radius", &config->marker.body_radius);
  marker.CheckUnknown();
  detection.Get("laser_range_noise", &config->laser_range_noise);
  detection.Get("max_time_difference", &config->max_time_difference);
  ReadNameMap(detection, "robot_ids", &config->robot_ids);
  detection.Get("mask_seen_robots", &config->mask_seen_robots);
  detection.Get("mask_laser_bodies", &config->mask_laser_bodies);
  detection.CheckUnknown();
}

}  // namespace

bool ParseAgentConfig(const std::string& yaml_text, const std::string& name,
                      const std::string& base_dir, AgentConfig* config, std::string* error) {
  *config = AgentConfig();
  YAML::Node root_node;
  try {
    root_node = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    *error = name + ": not valid YAML: " + e.what();
    return false;
  }
  std::string problem;
  if (!root_node.IsMap()) {
    *error = name + ": expected a map of settings (robot:, server:, source:, ...)";
    return false;
  }
  Fields root(root_node, "", &problem);
  ReadRobot(root, config, &problem);
  Fields server(root.Child("server"), "server", &problem);
  server.Get("address", &config->server_address);
  server.CheckUnknown();
  Fields outbox(root.Child("outbox"), "outbox", &problem);
  outbox.Get("path", &config->outbox_path);
  outbox.CheckUnknown();
  config->outbox_path = Resolve(base_dir, config->outbox_path);
  Fields slam(root.Child("slam"), "slam", &problem);
  slam.Get("algorithm", &config->slam.algorithm);
  slam.Get("resolution", &config->slam.resolution);
  slam.Get("max_range", &config->slam.max_range);
  slam.Get("submap_scans", &config->slam.submap_scans);
  slam.Get("submap_travel", &config->slam.submap_travel);
  slam.Get("min_translation", &config->slam.min_translation);
  slam.Get("min_rotation", &config->slam.min_rotation);
  slam.CheckUnknown();
  ReadSource(root, base_dir, &config->source, &problem);
  ReadUpload(root, &config->upload, &problem);
  Fields map(root.Child("map"), "map", &problem);
  map.Get("subscribe", &config->map.subscribe);
  map.Get("file", &config->map.file);
  ReadBackoff(map, "reconnect", &config->map.reconnect, &problem);
  map.CheckUnknown();
  config->map.file = Resolve(base_dir, config->map.file);
  ReadDetection(root, base_dir, &config->detection, &problem);
  ReadLocalization(root, base_dir, &config->localization, &problem);
  Fields status(root.Child("status"), "status", &problem);
  status.Get("period", &config->status_period);
  status.CheckUnknown();
  root.CheckUnknown();
  if (problem.empty() && !ValidateAgentConfig(*config, &problem)) {
    // ValidateAgentConfig names the field already.
  }
  if (!problem.empty()) {
    *error = name + ": " + problem;
    return false;
  }
  return true;
}

bool LoadAgentConfig(const std::string& path, AgentConfig* config, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot read the configuration file";
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  return ParseAgentConfig(text.str(), path, base_dir, config, error);
}

}  // namespace fleetmap

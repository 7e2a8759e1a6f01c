#include "robot_agent/sim/scenario.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#ifndef FLEETMAP_SIM_SOURCE_DIR
#define FLEETMAP_SIM_SOURCE_DIR "robot_agent/sim"
#endif

namespace fleetmap::sim {
namespace {

namespace fs = std::filesystem;

// Collects the first error with its field path; every check returns false once failed.
class Checker {
 public:
  Checker(std::string file, std::string* error) : file_(std::move(file)), error_(error) {}

  bool Fail(const std::string& field, const std::string& message) {
    *error_ = file_ + ": " + (field.empty() ? "" : field + ": ") + message;
    return false;
  }

  bool Keys(const YAML::Node& node, const std::string& field,
            const std::set<std::string>& allowed) {
    if (!node) return true;
    if (!node.IsMap()) return Fail(field, "expected a mapping of keys");
    for (const auto& entry : node) {
      const std::string key = entry.first.as<std::string>();
      if (!allowed.count(key)) {
        std::string known;
        for (const std::string& k : allowed) known += (known.empty() ? "" : ", ") + k;
        return Fail(Join(field, key), "unknown key (known: " + known + ")");
      }
    }
    return true;
  }

  bool Number(const YAML::Node& node, const std::string& key, const std::string& field,
              double* out) {
    const YAML::Node value = node[key];
    if (!value) return true;
    try {
      *out = value.as<double>();
    } catch (const YAML::Exception&) {
      return Fail(Join(field, key), "expected a number");
    }
    if (!std::isfinite(*out)) return Fail(Join(field, key), "must be finite");
    return true;
  }
  bool Positive(const YAML::Node& node, const std::string& key, const std::string& field,
                double* out) {
    if (!Number(node, key, field, out)) return false;
    if (!(*out > 0.0)) return Fail(Join(field, key), "must be > 0, got " + Str(*out));
    return true;
  }
  bool NonNegative(const YAML::Node& node, const std::string& key, const std::string& field,
                   double* out) {
    if (!Number(node, key, field, out)) return false;
    if (*out < 0.0) return Fail(Join(field, key), "must be >= 0, got " + Str(*out));
    return true;
  }
  bool Integer(const YAML::Node& node, const std::string& key, const std::string& field,
               int min_value, int* out) {
    const YAML::Node value = node[key];
    if (!value) return true;
    try {
      *out = value.as<int>();
    } catch (const YAML::Exception&) {
      return Fail(Join(field, key), "expected an integer");
    }
    if (*out < min_value) {
      return Fail(Join(field, key), "must be >= " + std::to_string(min_value));
    }
    return true;
  }

  static std::string Join(const std::string& field, const std::string& key) {
    return field.empty() ? key : field + "." + key;
  }
  static std::string Str(double value) {
    std::ostringstream os;
    os << value;
    return os.str();
  }

 private:
  std::string file_;
  std::string* error_;
};

bool ParsePose(Checker* c, const YAML::Node& node, const std::string& field, Rigid2d* pose) {
  if (!c->Keys(node, field, {"x", "y", "theta"})) return false;
  if (!node["x"] || !node["y"]) return c->Fail(field, "a pose needs x and y (theta optional)");
  double x = 0, y = 0, theta = 0;
  if (!c->Number(node, "x", field, &x) || !c->Number(node, "y", field, &y) ||
      !c->Number(node, "theta", field, &theta)) {
    return false;
  }
  *pose = Rigid2d(x, y, theta);
  return true;
}

bool ParseLaser(Checker* c, const YAML::Node& node, LaserOptions* laser) {
  const std::string f = "laser";
  if (!c->Keys(node, f, {"rate", "beams", "fov_deg", "max_range", "min_range", "range_noise",
                         "dropout_probability", "mount"})) {
    return false;
  }
  if (!node) return true;
  if (!c->Positive(node, "rate", f, &laser->rate_hz) ||
      !c->Integer(node, "beams", f, 2, &laser->beams) ||
      !c->Positive(node, "fov_deg", f, &laser->fov_deg) ||
      !c->Positive(node, "max_range", f, &laser->max_range) ||
      !c->NonNegative(node, "min_range", f, &laser->min_range) ||
      !c->NonNegative(node, "range_noise", f, &laser->range_noise) ||
      !c->NonNegative(node, "dropout_probability", f, &laser->dropout_probability)) {
    return false;
  }
  if (laser->fov_deg > 360.0) return c->Fail(f + ".fov_deg", "must be <= 360");
  if (laser->dropout_probability > 1.0) {
    return c->Fail(f + ".dropout_probability", "must be in [0, 1]");
  }
  if (node["mount"] && !ParsePose(c, node["mount"], f + ".mount", &laser->mount)) return false;
  return true;
}

bool ParseCamera(Checker* c, const YAML::Node& node, CameraOptions* camera) {
  const std::string f = "camera";
  if (!c->Keys(node, f, {"enabled", "rate", "width", "height", "hfov_deg", "mount_x", "mount_y",
                         "mount_z", "mount_yaw", "max_depth", "pixel_noise",
                         "lighting_variation", "save_every", "save_in_view_range"})) {
    return false;
  }
  if (!node) return true;
  if (node["enabled"]) {
    try {
      camera->enabled = node["enabled"].as<bool>();
    } catch (const YAML::Exception&) {
      return c->Fail(f + ".enabled", "expected true or false");
    }
  }
  if (!c->Positive(node, "rate", f, &camera->rate_hz) ||
      !c->Integer(node, "width", f, 16, &camera->width) ||
      !c->Integer(node, "height", f, 16, &camera->height) ||
      !c->Positive(node, "hfov_deg", f, &camera->hfov_deg) ||
      !c->Number(node, "mount_x", f, &camera->mount_x) ||
      !c->Number(node, "mount_y", f, &camera->mount_y) ||
      !c->Positive(node, "mount_z", f, &camera->mount_z) ||
      !c->Number(node, "mount_yaw", f, &camera->mount_yaw) ||
      !c->Positive(node, "max_depth", f, &camera->max_depth) ||
      !c->NonNegative(node, "pixel_noise", f, &camera->pixel_noise) ||
      !c->NonNegative(node, "lighting_variation", f, &camera->lighting_variation) ||
      !c->Integer(node, "save_every", f, 1, &camera->save_every) ||
      !c->NonNegative(node, "save_in_view_range", f, &camera->save_in_view_range)) {
    return false;
  }
  if (camera->hfov_deg >= 170.0) return c->Fail(f + ".hfov_deg", "must be < 170 (pinhole)");
  if (camera->width > 4096 || camera->height > 4096) {
    return c->Fail(f, "width and height must be <= 4096");
  }
  return true;
}

bool ParseOdometry(Checker* c, const YAML::Node& node, OdometryOptions* odometry) {
  const std::string f = "odometry";
  if (!c->Keys(node, f, {"rate", "baseline", "wheel_noise", "left_wheel_error",
                         "right_wheel_error", "baseline_error"})) {
    return false;
  }
  if (!node) return true;
  if (!c->Positive(node, "rate", f, &odometry->rate_hz) ||
      !c->Positive(node, "baseline", f, &odometry->baseline) ||
      !c->NonNegative(node, "wheel_noise", f, &odometry->wheel_noise) ||
      !c->Number(node, "left_wheel_error", f, &odometry->left_wheel_error) ||
      !c->Number(node, "right_wheel_error", f, &odometry->right_wheel_error) ||
      !c->Number(node, "baseline_error", f, &odometry->baseline_error)) {
    return false;
  }
  if (std::abs(odometry->left_wheel_error) >= 0.5 ||
      std::abs(odometry->right_wheel_error) >= 0.5 || std::abs(odometry->baseline_error) >= 0.5) {
    return c->Fail(f, "wheel and baseline errors are fractions and must lie in (-0.5, 0.5)");
  }
  return true;
}

bool ParseBody(Checker* c, const YAML::Node& node, RobotBody* body) {
  const std::string f = "robot_body";
  if (!c->Keys(node, f, {"radius", "body_height", "marker_radius", "marker_z_min",
                         "marker_z_max"})) {
    return false;
  }
  if (!node) return true;
  if (!c->Positive(node, "radius", f, &body->radius) ||
      !c->Positive(node, "body_height", f, &body->body_height) ||
      !c->Positive(node, "marker_radius", f, &body->marker_radius) ||
      !c->NonNegative(node, "marker_z_min", f, &body->marker_z_min) ||
      !c->Positive(node, "marker_z_max", f, &body->marker_z_max)) {
    return false;
  }
  if (body->marker_z_max <= body->marker_z_min) {
    return c->Fail(f, "marker_z_max must be above marker_z_min");
  }
  return true;
}

bool ParseWaypoint(Checker* c, const YAML::Node& node, const std::string& field,
                   Waypoint* waypoint) {
  if (node.IsScalar()) {
    waypoint->place = node.as<std::string>();
    return true;
  }
  if (node.IsSequence() && node.size() == 2) {
    try {
      waypoint->position = Eigen::Vector2d(node[0].as<double>(), node[1].as<double>());
      return true;
    } catch (const YAML::Exception&) {
    }
  }
  if (node.IsMap() && node["x"] && node["y"]) {
    Rigid2d pose;
    if (!ParsePose(c, node, field, &pose)) return false;
    waypoint->position = pose.translation();
    return true;
  }
  return c->Fail(field, "a waypoint is a place name, [x, y] or {x: .., y: ..}");
}

bool ParseRobot(Checker* c, const YAML::Node& node, int index, RobotSpec* robot) {
  const std::string f = "robots[" + std::to_string(index) + "]";
  if (!node.IsMap()) return c->Fail(f, "expected a mapping");
  if (!c->Keys(node, f, {"name", "start", "route", "start_delay"})) return false;
  robot->name = node["name"] ? node["name"].as<std::string>() : "robot" + std::to_string(index + 1);
  if (robot->name.empty() || robot->name.find_first_of(" /\\\t") != std::string::npos) {
    return c->Fail(f + ".name", "must be non-empty without spaces or slashes");
  }
  const YAML::Node start = node["start"];
  if (!start) return c->Fail(f, "missing 'start' (a place name or {x, y, theta})");
  if (start.IsScalar()) {
    robot->start_place = start.as<std::string>();
  } else if (!ParsePose(c, start, f + ".start", &robot->start)) {
    return false;
  }
  if (!c->NonNegative(node, "start_delay", f, &robot->start_delay)) return false;
  const YAML::Node route = node["route"];
  const std::string rf = f + ".route";
  if (!route) return true;  // a robot that stands still (e.g. an observer)
  if (!c->Keys(route, rf, {"waypoints", "laps", "speed"})) return false;
  if (!c->Integer(route, "laps", rf, 1, &robot->laps)) return false;
  if (!c->Number(route, "speed", rf, &robot->speed)) return false;
  if (!(robot->speed > 0.0)) {
    return c->Fail(rf + ".speed", "must be > 0, got " + Checker::Str(robot->speed));
  }
  if (robot->speed > 3.0) return c->Fail(rf + ".speed", "must be <= 3 m/s");
  const YAML::Node waypoints = route["waypoints"];
  if (waypoints && !waypoints.IsSequence()) return c->Fail(rf + ".waypoints", "expected a list");
  for (size_t i = 0; waypoints && i < waypoints.size(); ++i) {
    Waypoint waypoint;
    if (!ParseWaypoint(c, waypoints[i], rf + ".waypoints[" + std::to_string(i) + "]",
                       &waypoint)) {
      return false;
    }
    robot->waypoints.push_back(waypoint);
  }
  return true;
}

bool ResolveWorld(Checker* c, const std::string& base_dir,
                  const std::vector<std::string>& worlds_dirs, Scenario* scenario) {
  const std::string& world = scenario->world;
  if (world.empty()) return c->Fail("world", "missing (a world name such as 'department')");
  const bool is_path = world.find('/') != std::string::npos ||
                       (world.size() > 5 && world.substr(world.size() - 5) == ".yaml");
  std::vector<fs::path> candidates;
  if (is_path) {
    candidates.push_back(fs::path(world).is_absolute() ? fs::path(world)
                                                       : fs::path(base_dir) / world);
  } else {
    for (const std::string& dir : worlds_dirs) candidates.push_back(fs::path(dir) / world);
    candidates.push_back(fs::path(base_dir) / ".." / "worlds" / world);
    candidates.push_back(fs::path(ShippedWorldsDir()) / world);
    for (fs::path& candidate : candidates) candidate += ".world.yaml";
  }
  for (const fs::path& candidate : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      scenario->world_path = candidate.lexically_normal().string();
      return true;
    }
  }
  std::string looked;
  for (const fs::path& candidate : candidates) {
    looked += (looked.empty() ? "" : ", ") + candidate.lexically_normal().string();
  }
  return c->Fail("world", "unknown world '" + world + "' (looked for " + looked +
                              "; shipped worlds: rectangle, department, building)");
}

}  // namespace

std::string Waypoint::Describe() const {
  if (!place.empty()) return "'" + place + "'";
  std::ostringstream os;
  os << "(" << position.x() << ", " << position.y() << ")";
  return os.str();
}

std::string ShippedWorldsDir() { return std::string(FLEETMAP_SIM_SOURCE_DIR) + "/worlds"; }
std::string ShippedScenariosDir() { return std::string(FLEETMAP_SIM_SOURCE_DIR) + "/scenarios"; }

bool ParseScenario(const std::string& yaml_text, const std::string& base_dir,
                   Scenario* scenario, std::string* error,
                   const std::vector<std::string>& worlds_dirs) {
  Checker c("scenario", error);
  return [&]() {
    YAML::Node root;
    try {
      root = YAML::Load(yaml_text);
    } catch (const YAML::Exception& e) {
      return c.Fail("", std::string("invalid YAML: ") + e.what());
    }
    if (!root.IsMap()) return c.Fail("", "expected a mapping at the top level");
    try {
      *scenario = Scenario();
      if (!c.Keys(root, "", {"name", "world", "seed", "duration", "time_step", "start_time",
                             "laser", "camera", "odometry", "robot_body", "robots"})) {
        return false;
      }
      scenario->name = root["name"].as<std::string>("scenario");
      scenario->world = root["world"].as<std::string>("");
      if (root["seed"]) {
        try {
          scenario->seed = root["seed"].as<uint64_t>();
        } catch (const YAML::Exception&) {
          return c.Fail("seed", "expected a non-negative integer");
        }
      }
      if (!c.NonNegative(root, "duration", "", &scenario->duration) ||
          !c.Positive(root, "time_step", "", &scenario->time_step) ||
          !c.NonNegative(root, "start_time", "", &scenario->start_time)) {
        return false;
      }
      if (scenario->time_step > 0.1) return c.Fail("time_step", "must be <= 0.1 s");
      if (!ParseLaser(&c, root["laser"], &scenario->laser) ||
          !ParseCamera(&c, root["camera"], &scenario->camera) ||
          !ParseOdometry(&c, root["odometry"], &scenario->odometry) ||
          !ParseBody(&c, root["robot_body"], &scenario->body)) {
        return false;
      }
      const YAML::Node robots = root["robots"];
      if (!robots || !robots.IsSequence() || robots.size() == 0) {
        return c.Fail("robots", "expected a non-empty list of robots");
      }
      std::set<std::string> names;
      for (size_t i = 0; i < robots.size(); ++i) {
        RobotSpec robot;
        if (!ParseRobot(&c, robots[i], static_cast<int>(i), &robot)) return false;
        if (!names.insert(robot.name).second) {
          return c.Fail("robots[" + std::to_string(i) + "].name",
                        "duplicate robot name '" + robot.name + "'");
        }
        scenario->robots.push_back(robot);
      }
    } catch (const YAML::Exception& e) {
      return c.Fail("", std::string("malformed value: ") + e.what());
    }
    return ResolveWorld(&c, base_dir, worlds_dirs, scenario);
  }();
}

bool LoadScenario(const std::string& path, Scenario* scenario, std::string* error,
                  const std::vector<std::string>& worlds_dirs) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open scenario file " + path;
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  const std::string base_dir = fs::path(path).parent_path().string();
  if (!ParseScenario(text.str(), base_dir.empty() ? "." : base_dir, scenario, error,
                     worlds_dirs)) {
    // Name the real file instead of the generic "scenario" prefix.
    if (error->rfind("scenario: ", 0) == 0) *error = path + ": " + error->substr(10);
    return false;
  }
  return true;
}

}  // namespace fleetmap::sim

#ifndef FLEETMAP_ROBOT_AGENT_SIM_SCENARIO_H_
#define FLEETMAP_ROBOT_AGENT_SIM_SCENARIO_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"

namespace fleetmap::sim {

// SICK LMS200-like defaults: 181 beams over 180 degrees, 8 m so long corridors have no end.
struct LaserOptions {
  double rate_hz = 10.0;
  int beams = 181;
  double fov_deg = 180.0;
  double max_range = 8.0;
  double min_range = 0.02;
  double range_noise = 0.01;           // Gaussian sigma, metres
  double dropout_probability = 0.005;  // per beam: reported as no-return
  Rigid2d mount;                       // sensor_in_robot
};

// Pinhole colour camera looking forward; fx = fy from the horizontal field, principal point at
// the image centre.
struct CameraOptions {
  bool enabled = true;
  double rate_hz = 5.0;
  int width = 640;
  int height = 480;
  double hfov_deg = 60.0;
  double mount_x = 0.1;  // camera centre in the robot frame, metres
  double mount_y = 0.0;
  double mount_z = 0.55;    // height above the floor
  double mount_yaw = 0.0;   // radians, 0 = looking along the robot's x axis
  double max_depth = 40.0;  // walls beyond are drawn as fog-grey
  double pixel_noise = 3.0;          // Gaussian sigma per channel, grey levels
  double lighting_variation = 0.25;  // relative amplitude of brightness changes
  // Which rendered frames fleetmap-sim writes to PNG (the library API renders them all):
  // every `save_every`-th frame, plus every frame with another robot in the field of view within
  // `save_in_view_range` metres (occluded or not), so detection data keep all the positives.
  // PNG encoding of noisy 640x480 frames costs ~30 ms each, far more than rendering them.
  int save_every = 5;
  double save_in_view_range = 8.0;
};

// Wheel odometry of a differential drive. Each wheel's travel d is reported as
// d * (1 + wheel_error) + N(0, wheel_noise^2 * |d|); the heading uses baseline * (1 +
// baseline_error). Zero everywhere gives odometry equal to the ground truth.
struct OdometryOptions {
  double rate_hz = 20.0;
  double baseline = 0.4;  // metres between the wheels
  double wheel_noise = 0.005;
  double left_wheel_error = 0.001;
  double right_wheel_error = -0.0005;
  double baseline_error = 0.01;
};

// Every robot looks the same apart from its marker colour: a dark cylinder (what the laser of
// another robot sees) with a coloured cylindrical marker band above it.
struct RobotBody {
  double radius = 0.2;
  double body_height = 0.35;
  double marker_radius = 0.2;
  double marker_z_min = 0.35;
  double marker_z_max = 0.65;
};

// A route point: a place name of the world, or a position.
struct Waypoint {
  std::string place;  // empty for a position
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  std::string Describe() const;
};

struct RobotSpec {
  std::string name;
  std::string start_place;  // when set, the start pose is the place's position and heading
  Rigid2d start;
  std::vector<Waypoint> waypoints;
  int laps = 1;          // the waypoint list is driven this many times
  double speed = 0.5;    // m/s
  double start_delay = 0.0;  // seconds standing still before driving
};

struct Scenario {
  std::string name;
  std::string world;       // as written in the file
  std::string world_path;  // resolved file
  uint64_t seed = 1;
  double duration = 0.0;   // seconds; 0 = until every route is done
  double time_step = 0.02;
  double start_time = 0.0;  // timestamp of the first tick
  LaserOptions laser;
  CameraOptions camera;
  OdometryOptions odometry;
  RobotBody body;
  std::vector<RobotSpec> robots;
};

// Parses a scenario file and checks everything that needs no world: types, unknown keys (typos),
// ranges (negative speed, zero rates), duplicate robot names, and that the world file exists.
// Messages name the file and the field, e.g. "s.yaml: robots[1].route.speed: must be > 0, got
// -0.5". Worlds named without a path are looked up as `<name>.world.yaml` in `worlds_dirs`
// (in order), then beside the scenario in ../worlds/, then in the shipped worlds folder.
bool LoadScenario(const std::string& path, Scenario* scenario, std::string* error,
                  const std::vector<std::string>& worlds_dirs = {});
// The same from YAML text; `base_dir` resolves relative world paths.
bool ParseScenario(const std::string& yaml_text, const std::string& base_dir,
                   Scenario* scenario, std::string* error,
                   const std::vector<std::string>& worlds_dirs = {});

// The folder of worlds shipped with the source tree.
std::string ShippedWorldsDir();
std::string ShippedScenariosDir();

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_SCENARIO_H_

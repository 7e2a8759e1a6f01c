#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_SYNTHETIC_SYNTHETIC_WORLD_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_SYNTHETIC_SYNTHETIC_WORLD_H_

// A tiny renderer of rooms with marked robots: camera images and laser scans with exact ground
// truth, for the detector's tests and benchmark. Walls are vertical segments, robots are a body
// cylinder with a coloured marker cylinder on top, posters are flat coloured patches on walls.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/detection/camera_model.h"
#include "robot_agent/detection/image.h"
#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::synthetic {

struct Bgr {
  double b = 0.0, g = 0.0, r = 0.0;  // 0..255
};

struct Wall {
  Eigen::Vector2d a, b;
  Bgr colour{170, 180, 190};
};

struct Poster {  // a flat patch in front of a wall, between two heights
  Eigen::Vector2d a, b;
  double bottom = 0.35, top = 0.65;
  Bgr colour;
};

struct Robot {
  std::string id;
  Rigid2d pose;  // robot in world
  Bgr marker_colour;
};

struct World {
  std::vector<Wall> walls;
  std::vector<Poster> posters;
  std::vector<Robot> robots;
  double wall_height = 2.5;
  Bgr floor{60, 95, 125};
  Bgr ceiling{225, 225, 225};
  Bgr body{50, 50, 50};
};

// Marker colours of robots "robot1".."robot4": green (the paper's), red, blue, yellow.
std::vector<Robot> DefaultRobots(int count);
void AddRoom(const Eigen::Vector2d& min, const Eigen::Vector2d& max, World* world);

struct RenderOptions {
  double light_gain = 1.0;    // global illumination: < 1 dark, > 1 bright (saturates)
  double noise_sigma = 4.0;   // grey levels
  uint32_t seed = 1;
};

// The image seen by the camera of robot `observer_id` at `observer_in_world` (the observer
// itself is not drawn).
BgrImage RenderImage(const World& world, const std::string& observer_id,
                     const Rigid2d& observer_in_world, const CameraModel& camera,
                     const MarkerGeometry& geometry, const RenderOptions& options);

struct LaserOptions {
  int beams = 181;
  float angle_min = static_cast<float>(-M_PI / 2);
  float angle_increment = static_cast<float>(M_PI / 180);
  float range_max = 8.0f;
  double noise_sigma = 0.01;
  Rigid2d sensor_in_robot;
  uint32_t seed = 1;
};

// The laser scan: walls and the other robots' bodies (posters are flat on walls).
LaserScan RenderScan(const World& world, const std::string& observer_id,
                     const Rigid2d& observer_in_world, const MarkerGeometry& geometry,
                     const LaserOptions& options, double timestamp = 0.0);

// Where every other robot truly is, and whether the camera sees all of its marker.
struct Sighting {
  std::string robot_id;
  Eigen::Vector2d position_in_observer = Eigen::Vector2d::Zero();  // robot frame
  double camera_range = 0.0;    // camera to marker axis
  double camera_bearing = 0.0;  // camera frame
  bool fully_in_view = false;   // the whole marker inside the horizontal field
  bool partly_in_view = false;
  bool occluded = false;        // a wall or another robot hides part of the marker
};
std::vector<Sighting> TrueSightings(const World& world, const std::string& observer_id,
                                    const Rigid2d& observer_in_world, const CameraModel& camera,
                                    const MarkerGeometry& geometry);

}  // namespace fleetmap::synthetic

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_SYNTHETIC_SYNTHETIC_WORLD_H_

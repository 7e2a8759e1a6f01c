#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_SYNTHETIC_SYNTHETIC_DATASET_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_SYNTHETIC_SYNTHETIC_DATASET_H_

// Random synthetic frames (a room, robots, same-coloured posters, lighting) with ground truth,
// and a colour model learned from them, for tests and the benchmark.

#include <cstdint>
#include <string>
#include <vector>

#include "robot_agent/detection/calibration.h"
#include "robot_agent/detection/colour_model.h"
#include "robot_agent/detection/synthetic/synthetic_world.h"

namespace fleetmap::synthetic {

struct SceneOptions {
  int robots = 4;               // including the observer, at most 4
  int posters = 3;              // same-coloured distractors on the walls
  Eigen::Vector2d room_size{14.0, 10.0};
  double in_view_probability = 0.75;  // chance a robot is placed inside the camera's field
  double max_range = 9.0;
  double min_light = 0.5, max_light = 1.5;
  double pixel_noise = 4.0;
  double laser_noise = 0.01;
};

struct Frame {
  World world;
  std::string observer_id;
  Rigid2d observer_in_world;
  double light_gain = 1.0;
  BgrImage image;
  LaserScan scan;
  std::vector<Sighting> truth;
};

Frame MakeRandomFrame(const CameraModel& camera, const MarkerGeometry& geometry,
                      const LaserOptions& laser, const SceneOptions& options, uint32_t seed);

// Boxes of the markers fully in view and not occluded (what a labeller would mark).
std::vector<LabelledMarker> LabelsFor(const Frame& frame, const CameraModel& camera,
                                      const MarkerGeometry& geometry);

// Calibrates on `frames` random frames (seeds seed, seed + 1, ...).
ColourModel LearnColourModel(const CameraModel& camera, const MarkerGeometry& geometry,
                             const SceneOptions& options, int frames, uint32_t seed);

}  // namespace fleetmap::synthetic

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_SYNTHETIC_SYNTHETIC_DATASET_H_

#include "robot_agent/agent/sim_detection_setup.h"

#include <cmath>
#include <vector>

#include "robot_agent/detection/calibration.h"
#include "robot_agent/sim/rng.h"

namespace fleetmap {
namespace {

constexpr sim::Rgb kTrainingBodyColor{55, 55, 60};  // the simulator's dark robot body

// Observer poses for the training views: the world's named places and the robots' starts.
std::vector<Rigid2d> TrainingPoses(const sim::Simulation& simulation) {
  std::vector<Rigid2d> poses;
  for (const sim::Place& place : simulation.world().places) {
    poses.emplace_back(place.position, place.heading);
  }
  for (const sim::RobotSpec& robot : simulation.scenario().robots) {
    if (robot.start_place.empty()) {
      poses.push_back(robot.start);
    } else if (const auto place = simulation.world().FindPlace(robot.start_place)) {
      poses.emplace_back(place->position, place->heading);
    }
  }
  return poses;
}

// True when a marker centred at `center` stands in free space and the camera sees all of it.
bool MarkerFits(const sim::World& world, const Eigen::Vector2d& camera,
                const Eigen::Vector2d& center, double radius) {
  for (int i = 0; i < 12; ++i) {
    const double a = i * M_PI / 6.0;
    if (world.IsBlockedAt(center + (radius + 0.05) * Eigen::Vector2d(std::cos(a), std::sin(a)))) {
      return false;
    }
  }
  const Eigen::Vector2d toward = (center - camera).normalized();
  const Eigen::Vector2d side(-toward.y(), toward.x());
  return world.LineOfSight(camera, center) && world.LineOfSight(camera, center + radius * side) &&
         world.LineOfSight(camera, center - radius * side);
}

struct Placed {
  int robot = 0;
  double range = 0.0;    // camera to marker axis
  double bearing = 0.0;  // camera frame
};

}  // namespace

bool MakeSimDetectionSetup(const sim::Simulation& simulation,
                           const SimColourLearningOptions& options, DetectionSetup* setup,
                           std::string* error) {
  const sim::Scenario& scenario = simulation.scenario();
  const sim::CameraModel& renderer = simulation.camera();
  DetectionSetup result;
  CameraModel& camera = result.camera;
  camera.width = scenario.camera.width;
  camera.height = scenario.camera.height;
  camera.fx = renderer.intrinsics().fx;
  camera.fy = renderer.intrinsics().fy;
  // The simulator puts pixel edges at integers; the detector puts pixel centres there.
  camera.cx = renderer.intrinsics().cx - 0.5;
  camera.cy = renderer.intrinsics().cy - 0.5;
  camera.camera_in_robot = renderer.mount();
  camera.mount_height = scenario.camera.mount_z;
  result.geometry.body_radius = scenario.body.radius;
  result.geometry.marker_radius = scenario.body.marker_radius;
  result.geometry.marker_bottom = scenario.body.marker_z_min;
  result.geometry.marker_top = scenario.body.marker_z_max;
  result.laser_range_noise = scenario.laser.range_noise;
  if (!camera.IsValid(error) || !result.geometry.IsValid(error)) {
    *error = "simulator camera/marker: " + *error;
    return false;
  }

  const std::vector<Rigid2d> poses = TrainingPoses(simulation);
  const auto& robots = simulation.robots();
  const int n = static_cast<int>(robots.size());
  if (poses.empty() || n == 0) {
    *error = "simulator: no places or robots to learn marker colours from";
    return false;
  }
  const double r = result.geometry.marker_radius;
  const double variation = scenario.camera.lighting_variation;
  ColourCalibrator calibrator;
  sim::RgbImage rgb;
  BgrImage bgr(camera.width, camera.height);
  for (int k = 0; k < options.views; ++k) {
    const Rigid2d& base = poses[static_cast<size_t>(k) % poses.size()];
    const int turn = k / static_cast<int>(poses.size());
    const Rigid2d observer(base.translation(),
                           base.rotation() + turn * 0.5 * M_PI + 0.2 * ((k % 5) - 2));
    const Rigid2d camera_in_world = observer * camera.camera_in_robot;
    std::vector<Placed> placed;
    std::vector<sim::Cylinder> cylinders;
    for (int j = 0; j < std::min(3, n); ++j) {
      Placed marker;
      marker.robot = (k * 3 + j) % n;
      marker.bearing = (j == 0 ? 0.0 : (j == 1 ? -0.33 : 0.33)) + 0.05 * ((k % 3) - 1);
      const double phase = 0.618 * k + 0.37 * j;
      for (double range : {1.0 + 3.0 * (phase - std::floor(phase)), 1.2}) {
        marker.range = range;
        const Eigen::Vector2d center =
            camera_in_world *
            Eigen::Vector2d(range * std::cos(marker.bearing), range * std::sin(marker.bearing));
        bool apart = true;  // no marker hides part of another
        for (const Placed& other : placed) {
          apart &= std::abs(other.bearing - marker.bearing) >
                   std::asin(r / other.range) + std::asin(r / range) + 0.03;
        }
        if (!apart || !MarkerFits(simulation.world(), camera_in_world.translation(), center,
                                  std::max(r, scenario.body.radius))) {
          continue;
        }
        placed.push_back(marker);
        cylinders.push_back(
            {center, scenario.body.radius, 0.0, scenario.body.body_height, kTrainingBodyColor});
        cylinders.push_back({center, r, scenario.body.marker_z_min, scenario.body.marker_z_max,
                             robots[static_cast<size_t>(marker.robot)].marker});
        break;
      }
    }
    sim::Rng rng = sim::Rng::ForStream(options.seed, static_cast<uint64_t>(k));
    const double exposure = 1.0 + variation * (2.0 * rng.Uniform() - 1.0);
    renderer.Render(simulation.world(), observer, cylinders, exposure, &rng, &rgb);
    if (rgb.width != camera.width || rgb.height != camera.height) {
      *error = "simulator: rendered frame has an unexpected size";
      return false;
    }
    for (size_t i = 0; i + 2 < rgb.pixels.size(); i += 3) {
      bgr.data[i] = rgb.pixels[i + 2];
      bgr.data[i + 1] = rgb.pixels[i + 1];
      bgr.data[i + 2] = rgb.pixels[i];
    }
    std::vector<LabelledMarker> labels;
    for (const Placed& marker : placed) {
      const ImageBox box = ProjectMarker(camera, result.geometry, marker.range, marker.bearing);
      if (box.width <= 0 || box.height <= 0) continue;
      labels.push_back({robots[static_cast<size_t>(marker.robot)].name, box, false});
    }
    if (!calibrator.AddFrame(bgr.view(), labels, error)) return false;
  }
  for (const sim::SimRobotInfo& robot : robots) {
    if (calibrator.marker_pixels(robot.name) == 0) {
      *error = "simulator: could not show " + robot.name +
               "'s marker in any training view (raise detection.learn_views)";
      return false;
    }
  }
  result.colours = calibrator.Build();
  if (!result.colours.IsValid(error)) return false;
  *setup = std::move(result);
  return true;
}

}  // namespace fleetmap

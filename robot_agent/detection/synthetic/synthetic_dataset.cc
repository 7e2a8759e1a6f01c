#include "robot_agent/detection/synthetic/synthetic_dataset.h"

#include <cmath>
#include <random>

namespace fleetmap::synthetic {
namespace {

bool FarFromWalls(const Eigen::Vector2d& p, const Eigen::Vector2d& room, double margin) {
  return p.x() > margin && p.y() > margin && p.x() < room.x() - margin && p.y() < room.y() - margin;
}

}  // namespace

Frame MakeRandomFrame(const CameraModel& camera, const MarkerGeometry& geometry,
                      const LaserOptions& laser, const SceneOptions& options, uint32_t seed) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector2d room = options.room_size;
  Frame frame;
  AddRoom(Eigen::Vector2d::Zero(), room, &frame.world);
  // A partition wall with a gap, so that some robots are hidden.
  const double wall_x = room.x() * (0.35 + 0.3 * unit(engine));
  frame.world.walls.push_back({{wall_x, 0.0}, {wall_x, room.y() * (0.2 + 0.25 * unit(engine))}});

  frame.world.robots = DefaultRobots(options.robots);
  const double margin = geometry.body_radius + 0.3;
  const double half_fov = camera.HalfFieldOfView();
  std::vector<Eigen::Vector2d> placed;
  auto clear_of_others = [&](const Eigen::Vector2d& p) {
    if (std::abs(p.x() - wall_x) < margin) return false;
    for (const Eigen::Vector2d& q : placed) {
      if ((p - q).norm() < 2.0 * geometry.body_radius + 0.4) return false;
    }
    return true;
  };
  for (size_t i = 0; i < frame.world.robots.size(); ++i) {
    Robot& robot = frame.world.robots[i];
    Eigen::Vector2d position;
    for (int attempt = 0; attempt < 1000; ++attempt) {
      if (i > 0 && unit(engine) < options.in_view_probability) {
        const Rigid2d& observer = frame.world.robots[0].pose;
        const double range = 0.8 + (options.max_range - 0.8) * unit(engine);
        const double bearing = (2.0 * unit(engine) - 1.0) * (half_fov + 0.05);
        position = observer * Eigen::Vector2d(range * std::cos(bearing), range * std::sin(bearing));
      } else {
        position = Eigen::Vector2d(room.x() * unit(engine), room.y() * unit(engine));
      }
      if (FarFromWalls(position, room, margin) && clear_of_others(position)) break;
    }
    placed.push_back(position);
    robot.pose = Rigid2d(position, 2.0 * M_PI * unit(engine));
  }
  frame.observer_id = frame.world.robots[0].id;
  frame.observer_in_world = frame.world.robots[0].pose;

  // Posters: marker-coloured patches where the observer looks, at marker height or higher.
  for (int i = 0; i < options.posters && frame.world.robots.size() > 1; ++i) {
    const Robot& like = frame.world.robots[1 + engine() % (frame.world.robots.size() - 1)];
    const double angle = frame.observer_in_world.rotation() + (2.0 * unit(engine) - 1.0) * half_fov;
    const Eigen::Vector2d origin = frame.observer_in_world.translation();
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    // Find the wall the ray meets and lay the poster along it.
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector2d along = Eigen::Vector2d::UnitX();
    for (const Wall& wall : frame.world.walls) {
      const Eigen::Vector2d e = wall.b - wall.a;
      const double denom = dir.x() * e.y() - dir.y() * e.x();
      if (std::abs(denom) < 1e-9) continue;
      const Eigen::Vector2d w = wall.a - origin;
      const double t = (w.x() * e.y() - w.y() * e.x()) / denom;
      const double u = (w.x() * dir.y() - w.y() * dir.x()) / denom;
      if (t > 0.0 && u >= 0.0 && u <= 1.0 && t < best) {
        best = t;
        along = e.normalized();
      }
    }
    if (!std::isfinite(best)) continue;
    const Eigen::Vector2d center = origin + (best - 0.02) * dir;
    const double half_width = 0.5 * (0.15 + 0.45 * unit(engine));
    Poster poster;
    poster.a = center - half_width * along;
    poster.b = center + half_width * along;
    const double lift = unit(engine) < 0.5 ? 0.0 : 0.6 * unit(engine);
    poster.bottom = geometry.marker_bottom + lift;
    poster.top = geometry.marker_top + lift;
    poster.colour = like.marker_colour;
    frame.world.posters.push_back(poster);
  }

  frame.light_gain = options.min_light + (options.max_light - options.min_light) * unit(engine);
  RenderOptions render;
  render.light_gain = frame.light_gain;
  render.noise_sigma = options.pixel_noise;
  render.seed = seed;
  frame.image = RenderImage(frame.world, frame.observer_id, frame.observer_in_world, camera,
                            geometry, render);
  LaserOptions laser_options = laser;
  laser_options.noise_sigma = options.laser_noise;
  laser_options.seed = seed + 7919u;
  frame.scan = RenderScan(frame.world, frame.observer_id, frame.observer_in_world, geometry,
                          laser_options, seed);
  frame.truth = TrueSightings(frame.world, frame.observer_id, frame.observer_in_world, camera,
                              geometry);
  return frame;
}

std::vector<LabelledMarker> LabelsFor(const Frame& frame, const CameraModel& camera,
                                      const MarkerGeometry& geometry) {
  std::vector<LabelledMarker> labels;
  for (const Sighting& s : frame.truth) {
    if (!s.fully_in_view || s.occluded) continue;
    const ImageBox box = ProjectMarker(camera, geometry, s.camera_range, s.camera_bearing);
    if (box.width > 0 && box.height > 0) labels.push_back({s.robot_id, box});
  }
  return labels;
}

ColourModel LearnColourModel(const CameraModel& camera, const MarkerGeometry& geometry,
                             const SceneOptions& options, int frames, uint32_t seed) {
  ColourCalibrator calibrator;
  for (int i = 0; i < frames; ++i) {
    const Frame frame = MakeRandomFrame(camera, geometry, LaserOptions(), options, seed + i);
    std::string error;
    calibrator.AddFrame(frame.image.view(), LabelsFor(frame, camera, geometry), &error);
  }
  return calibrator.Build();
}

}  // namespace fleetmap::synthetic

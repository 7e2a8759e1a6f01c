#include "robot_agent/sim/laser_model.h"

#include <cmath>
#include <limits>

namespace fleetmap::sim {

double RayCircleDistance(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                         const Eigen::Vector2d& center, double radius) {
  const Eigen::Vector2d offset = origin - center;
  const double b = offset.dot(direction);
  const double c = offset.squaredNorm() - radius * radius;
  const double discriminant = b * b - c;
  if (c <= 0.0 || discriminant < 0.0) return std::numeric_limits<double>::infinity();
  const double t = -b - std::sqrt(discriminant);
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

LaserScan LaserModel::Scan(const World& world, const Rigid2d& robot_in_world,
                           const std::vector<Cylinder>& obstacles, double timestamp,
                           Rng* rng) const {
  const Rigid2d sensor_in_world = robot_in_world * options_.mount;
  const int beams = options_.beams;
  const double fov = options_.fov_deg * M_PI / 180.0;
  const double increment = fov / (beams - 1);
  const double angle_min = -0.5 * fov;
  // Casting a bit past max range lets noise push a wall just inside range out of it, as real
  // scanners do.
  const double cast_range = options_.max_range + 0.1;
  std::vector<float> ranges(static_cast<size_t>(beams));
  for (int i = 0; i < beams; ++i) {
    const double angle = sensor_in_world.rotation() + angle_min + i * increment;
    double range = world.CastRay(sensor_in_world.translation(), angle, cast_range).distance;
    const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
    for (const Cylinder& obstacle : obstacles) {
      range = std::min(range, RayCircleDistance(sensor_in_world.translation(), direction,
                                                obstacle.center, obstacle.radius));
    }
    if (rng != nullptr) {
      range += rng->Gaussian(options_.range_noise);
      if (options_.dropout_probability > 0.0 && rng->Uniform() < options_.dropout_probability) {
        range = std::numeric_limits<double>::infinity();
      }
    }
    ranges[static_cast<size_t>(i)] = static_cast<float>(range);
  }
  return MakeLaserScan(timestamp, static_cast<float>(angle_min), static_cast<float>(increment),
                       static_cast<float>(options_.min_range),
                       static_cast<float>(options_.max_range), ranges, options_.mount);
}

}  // namespace fleetmap::sim

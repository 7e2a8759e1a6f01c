#ifndef FLEETMAP_ROBOT_AGENT_SIM_LASER_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_SIM_LASER_MODEL_H_

#include <vector>

#include <Eigen/Core>

#include "robot_agent/sim/rng.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world.h"
#include "shared/core/laser_scan.h"

namespace fleetmap::sim {

// A vertical cylinder standing on the floor between z_min and z_max (robot bodies, markers).
struct Cylinder {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.0;
  double z_min = 0.0;
  double z_max = 0.0;
  Rgb color;
};

// Distance along the unit direction `direction` from `origin` to the circle, or +inf when the
// ray misses it or starts inside it.
double RayCircleDistance(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                         const Eigen::Vector2d& center, double radius);

// Range finder ray-cast on the world grid plus the other robots as circles.
class LaserModel {
 public:
  explicit LaserModel(const LaserOptions& options) : options_(options) {}

  // A scan from `robot_in_world` (the sensor sits at options.mount on the robot). Noise and
  // dropouts come from `rng`; pass nullptr for exact ranges.
  LaserScan Scan(const World& world, const Rigid2d& robot_in_world,
                 const std::vector<Cylinder>& obstacles, double timestamp, Rng* rng) const;

  const LaserOptions& options() const { return options_; }

 private:
  const LaserOptions options_;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_LASER_MODEL_H_

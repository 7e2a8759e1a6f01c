#include "robot_agent/localization/motion_model.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

OdometryParts DecomposeOdometry(const Rigid2d& odometry_delta) {
  OdometryParts parts;
  const double dx = odometry_delta.x();
  const double dy = odometry_delta.y();
  parts.trans = std::hypot(dx, dy);
  // Tiny translations have no meaningful direction: all rotation goes to rot2.
  if (parts.trans > 1e-4) {
    parts.rot1 = std::atan2(dy, dx);
    if (std::abs(parts.rot1) > M_PI / 2) {
      parts.rot1 = NormalizeAngle(parts.rot1 + M_PI);
      parts.trans = -parts.trans;
    }
  }
  parts.rot2 = NormalizeAngle(odometry_delta.rotation() - parts.rot1);
  return parts;
}

OdometrySampler::OdometrySampler(const Rigid2d& odometry_delta,
                                 const OdometryMotionModelOptions& options)
    : parts_(DecomposeOdometry(odometry_delta)) {
  const double r1 = parts_.rot1 * parts_.rot1;
  const double t = parts_.trans * parts_.trans;
  const double r2 = parts_.rot2 * parts_.rot2;
  rot1_std_ = std::max(std::sqrt(options.alpha1 * r1 + options.alpha2 * t),
                       options.min_rotation_std);
  trans_std_ = std::max(std::sqrt(options.alpha3 * t + options.alpha4 * (r1 + r2)),
                        options.min_translation_std);
  rot2_std_ = std::max(std::sqrt(options.alpha1 * r2 + options.alpha2 * t),
                       options.min_rotation_std);
}

Rigid2d OdometrySampler::Sample(const Rigid2d& robot_in_map, std::mt19937& rng) const {
  std::normal_distribution<double> normal(0.0, 1.0);
  const double rot1 = parts_.rot1 + rot1_std_ * normal(rng);
  const double trans = parts_.trans + trans_std_ * normal(rng);
  const double rot2 = parts_.rot2 + rot2_std_ * normal(rng);
  const double heading = robot_in_map.rotation() + rot1;
  return Rigid2d(robot_in_map.x() + trans * std::cos(heading),
                 robot_in_map.y() + trans * std::sin(heading), heading + rot2);
}

}  // namespace fleetmap

#ifndef FLEETMAP_SHARED_CORE_RIGID2D_H_
#define FLEETMAP_SHARED_CORE_RIGID2D_H_

#include <cmath>
#include <ostream>

#include <Eigen/Core>

namespace fleetmap {

// Wraps an angle into [-pi, pi).
double NormalizeAngle(double angle);

// A 2D rigid transform: rotation by `rotation()` radians followed by a translation.
// Name variables by the frames they connect, e.g. `robot_in_map` maps points in the robot frame
// into the map frame, so `map_point = robot_in_map * robot_point`.
class Rigid2d {
 public:
  Rigid2d() = default;
  Rigid2d(const Eigen::Vector2d& translation, double rotation)
      : translation_(translation), rotation_(NormalizeAngle(rotation)) {}
  Rigid2d(double x, double y, double rotation) : Rigid2d(Eigen::Vector2d(x, y), rotation) {}

  static Rigid2d Identity() { return Rigid2d(); }

  const Eigen::Vector2d& translation() const { return translation_; }
  double x() const { return translation_.x(); }
  double y() const { return translation_.y(); }
  // Always in [-pi, pi).
  double rotation() const { return rotation_; }
  Eigen::Matrix2d rotation_matrix() const;

  Rigid2d inverse() const;
  Rigid2d operator*(const Rigid2d& rhs) const;
  Eigen::Vector2d operator*(const Eigen::Vector2d& point) const;
  Eigen::Vector2f operator*(const Eigen::Vector2f& point) const;

  bool IsFinite() const { return translation_.allFinite() && std::isfinite(rotation_); }

 private:
  Eigen::Vector2d translation_ = Eigen::Vector2d::Zero();
  double rotation_ = 0.0;
};

// Linear interpolation of translation and shortest-arc interpolation of rotation;
// t = 0 gives `start`, t = 1 gives `end`.
Rigid2d Interpolate(const Rigid2d& start, const Rigid2d& end, double t);

std::ostream& operator<<(std::ostream& os, const Rigid2d& transform);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_RIGID2D_H_

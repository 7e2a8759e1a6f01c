#include "shared/core/rigid2d.h"

#include <Eigen/Geometry>

namespace fleetmap {

double NormalizeAngle(double angle) {
  if (!std::isfinite(angle)) return angle;
  if (angle >= -M_PI && angle < M_PI) return angle;
  double wrapped = std::fmod(angle + M_PI, 2.0 * M_PI);
  if (wrapped < 0.0) wrapped += 2.0 * M_PI;
  // fmod can land exactly on 2*pi through rounding; keep the half-open interval.
  if (wrapped >= 2.0 * M_PI) wrapped -= 2.0 * M_PI;
  return wrapped - M_PI;
}

Eigen::Matrix2d Rigid2d::rotation_matrix() const {
  return Eigen::Rotation2Dd(rotation_).toRotationMatrix();
}

Rigid2d Rigid2d::inverse() const {
  const Eigen::Matrix2d r_t = rotation_matrix().transpose();
  return Rigid2d(-(r_t * translation_), -rotation_);
}

Rigid2d Rigid2d::operator*(const Rigid2d& rhs) const {
  return Rigid2d(rotation_matrix() * rhs.translation_ + translation_, rotation_ + rhs.rotation_);
}

Eigen::Vector2d Rigid2d::operator*(const Eigen::Vector2d& point) const {
  return rotation_matrix() * point + translation_;
}

Eigen::Vector2f Rigid2d::operator*(const Eigen::Vector2f& point) const {
  const float c = static_cast<float>(std::cos(rotation_));
  const float s = static_cast<float>(std::sin(rotation_));
  return Eigen::Vector2f(c * point.x() - s * point.y() + static_cast<float>(translation_.x()),
                         s * point.x() + c * point.y() + static_cast<float>(translation_.y()));
}

Rigid2d Interpolate(const Rigid2d& start, const Rigid2d& end, double t) {
  const Eigen::Vector2d translation =
      start.translation() + t * (end.translation() - start.translation());
  const double delta = NormalizeAngle(end.rotation() - start.rotation());
  return Rigid2d(translation, start.rotation() + t * delta);
}

std::ostream& operator<<(std::ostream& os, const Rigid2d& transform) {
  return os << "[x=" << transform.x() << ", y=" << transform.y()
            << ", theta=" << transform.rotation() << "]";
}

}  // namespace fleetmap

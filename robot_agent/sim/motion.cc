#include "robot_agent/sim/motion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetmap::sim {

Rigid2d ApplyArc(const Rigid2d& pose, double distance, double rotation) {
  double dx = distance;
  double dy = 0.0;
  if (std::abs(rotation) > 1e-9) {
    const double radius = distance / rotation;
    dx = radius * std::sin(rotation);
    dy = radius * (1.0 - std::cos(rotation));
  }
  return pose * Rigid2d(dx, dy, rotation);
}

PathFollower::PathFollower(Path path, double speed, double robot_radius,
                           const FollowerOptions& options)
    : path_(std::move(path)), speed_(speed), radius_(robot_radius), options_(options) {
  cumulative_.push_back(0.0);
  for (size_t i = 1; i < path_.size(); ++i) {
    cumulative_.push_back(cumulative_.back() + (path_[i] - path_[i - 1]).norm());
  }
  done_ = path_.size() < 2;
}

Eigen::Vector2d PathFollower::PointAt(double arc_length) const {
  if (arc_length >= cumulative_.back()) return path_.back();
  const size_t i = static_cast<size_t>(
      std::upper_bound(cumulative_.begin(), cumulative_.end(), arc_length) - cumulative_.begin());
  const double segment_length = cumulative_[i] - cumulative_[i - 1];
  const double t = segment_length > 0 ? (arc_length - cumulative_[i - 1]) / segment_length : 0;
  return path_[i - 1] + t * (path_[i] - path_[i - 1]);
}

void PathFollower::UpdateProgress(const Eigen::Vector2d& position) {
  // Closest point among the segments just ahead: progress never jumps back, and never far forward
  // where the path comes back on itself (laps, rooms entered and left by the same door).
  double best_distance = std::numeric_limits<double>::infinity();
  double best_progress = progress_;
  size_t best_segment = segment_;
  for (size_t i = segment_; i + 1 < path_.size(); ++i) {
    if (cumulative_[i] > progress_ + 1.0) break;
    const Eigen::Vector2d a = path_[i], b = path_[i + 1];
    const double length_sq = (b - a).squaredNorm();
    const double t =
        length_sq > 0 ? std::clamp((position - a).dot(b - a) / length_sq, 0.0, 1.0) : 0.0;
    const double d = (a + t * (b - a) - position).norm();
    const double s = cumulative_[i] + t * std::sqrt(length_sq);
    if (d < best_distance && s >= progress_) {
      best_distance = d;
      best_progress = s;
      best_segment = i;
    }
  }
  progress_ = best_progress;
  segment_ = best_segment;
}

VelocityCommand PathFollower::Compute(const Rigid2d& pose,
                                      const std::vector<Eigen::Vector2d>& others,
                                      const std::vector<bool>& yield_to,
                                      const PathPlanner& planner) {
  if (done_) return {};
  UpdateProgress(pose.translation());
  const double to_end = (path_.back() - pose.translation()).norm();
  if (cumulative_.back() - progress_ < options_.lookahead && to_end < options_.goal_tolerance) {
    done_ = true;
    return {};
  }
  Eigen::Vector2d target = PointAt(progress_ + options_.lookahead);
  const Eigen::Vector2d ahead = target - PointAt(progress_);
  double speed = speed_;
  for (size_t i = 0; i < others.size(); ++i) {
    const Eigen::Vector2d relative = pose.inverse() * others[i];
    if (relative.x() <= 0.0 || relative.norm() > options_.encounter_distance) continue;
    if (std::abs(relative.y()) > 1.5) continue;
    // Shift the target to the right of the path, as far as the walls allow.
    if (ahead.norm() > 1e-6) {
      const Eigen::Vector2d right(ahead.y() / ahead.norm(), -ahead.x() / ahead.norm());
      for (double fraction : {1.0, 0.66, 0.33}) {
        const Eigen::Vector2d shifted = target + fraction * options_.keep_right_offset * right;
        if (planner.DistanceToWall(shifted) >= radius_ + 0.1) {
          target = shifted;
          break;
        }
      }
    }
    const bool blocking = relative.x() < 2.0 * radius_ + 0.35 &&
                          std::abs(relative.y()) < 2.0 * radius_ + 0.05;
    if (blocking && yield_to[i]) speed = 0.0;
  }
  const Eigen::Vector2d local = pose.inverse() * target;
  const double heading_error = std::atan2(local.y(), local.x());
  VelocityCommand command;
  if (std::abs(heading_error) > options_.turn_in_place_angle) {
    command.angular = std::copysign(options_.max_angular_speed, heading_error);
    return command;
  }
  // Slow down for turns and at the end of the path.
  command.linear = std::min(speed * (1.0 - 0.6 * std::abs(heading_error) /
                                               options_.turn_in_place_angle),
                            std::max(0.05, 1.2 * to_end));
  if (speed == 0.0) command.linear = 0.0;
  command.angular = std::clamp(2.5 * heading_error, -options_.max_angular_speed,
                               options_.max_angular_speed);
  return command;
}

OdometryModel::OdometryModel(const OdometryOptions& options, uint64_t seed)
    : options_(options), rng_(seed) {}

void OdometryModel::Update(double distance, double rotation, double dt) {
  const double half_base = 0.5 * options_.baseline;
  double left = distance - half_base * rotation;
  double right = distance + half_base * rotation;
  // Noise variance grows with the distance each wheel travelled (a random walk per metre).
  left = left * (1.0 + options_.left_wheel_error) +
         rng_.Gaussian(options_.wheel_noise * std::sqrt(std::abs(left)));
  right = right * (1.0 + options_.right_wheel_error) +
          rng_.Gaussian(options_.wheel_noise * std::sqrt(std::abs(right)));
  const double measured_distance = 0.5 * (left + right);
  const double measured_rotation =
      (right - left) / (options_.baseline * (1.0 + options_.baseline_error));
  pose_ = ApplyArc(pose_, measured_distance, measured_rotation);
  if (dt > 0.0) {
    linear_velocity_ = measured_distance / dt;
    angular_velocity_ = measured_rotation / dt;
  }
}

}  // namespace fleetmap::sim

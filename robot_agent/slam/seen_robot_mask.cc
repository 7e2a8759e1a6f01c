#include "robot_agent/slam/seen_robot_mask.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

SeenRobotMask::SeenRobotMask(const SeenRobotMaskOptions& options) : options_(options) {}

void SeenRobotMask::AddOdometry(double time, const Rigid2d& pose) {
  if (!odometry_.empty() && time <= odometry_.back().first) return;
  odometry_.emplace_back(time, pose);
  // Kept a little longer than max_age: a detection can reach us after later scans.
  while (odometry_.size() > 2 && odometry_.front().first < time - 2.0 * options_.max_age - 1.0) {
    odometry_.pop_front();
  }
}

void SeenRobotMask::AddDetection(const RobotDetection& detection) {
  auto it = seen_.find(detection.observed_id);
  if (it == seen_.end() || it->second.timestamp <= detection.timestamp) seen_[detection.observed_id] = detection;
}

void SeenRobotMask::AddLaserBodies(double time, const std::vector<Eigen::Vector2d>& centers_in_robot) {
  Rigid2d odometry;
  const bool have_odometry = OdometryAt(time, &odometry);
  std::vector<Eigen::Vector2d> sighted;
  for (const Eigen::Vector2d& c : centers_in_robot) {
    if (have_odometry) sighted.push_back(odometry * c);
    if (!options_.laser_bodies_must_move || (have_odometry && Moved(time, sighted.back()))) {
      laser_bodies_.emplace_back(time, c);
    }
  }
  while (!body_sightings_.empty() &&
         body_sightings_.front().first < time - options_.body_track_window) {
    body_sightings_.pop_front();
  }
  for (const Eigen::Vector2d& p : sighted) body_sightings_.emplace_back(time, p);
  while (!laser_bodies_.empty() &&
         laser_bodies_.front().first < time - options_.max_laser_body_age) {
    laser_bodies_.pop_front();
  }
}

bool SeenRobotMask::Moved(double time, const Eigen::Vector2d& center) const {
  // The nearest earlier sighting it could have come from: on the spot means a fixed thing.
  double nearest = INFINITY;
  for (const auto& [then, p] : body_sightings_) {
    const double dt = time - then;
    if (dt <= 0.0 || dt > options_.body_track_window) continue;
    const double d = (p - center).norm();
    if (d <= options_.max_speed * dt + options_.min_body_motion) nearest = std::min(nearest, d);
  }
  return std::isfinite(nearest) && nearest > options_.min_body_motion;
}

bool SeenRobotMask::OdometryAt(double time, Rigid2d* pose) const {
  if (odometry_.empty() || time < odometry_.front().first ||
      time > odometry_.back().first + options_.max_odometry_gap) {
    return false;
  }
  for (size_t i = 1; i < odometry_.size(); ++i) {
    if (odometry_[i].first < time) continue;
    const auto& [t0, p0] = odometry_[i - 1];
    const auto& [t1, p1] = odometry_[i];
    const double s = (time - t0) / (t1 - t0);
    *pose = p0 * Rigid2d(s * (p0.inverse() * p1).translation(), s * (p0.inverse() * p1).rotation());
    return true;
  }
  *pose = odometry_.back().second;
  return true;
}

int SeenRobotMask::Apply(LaserScan* scan) const {
  Rigid2d now;
  if (empty() || !OdometryAt(scan->timestamp, &now)) return 0;
  // Our own motion since the latest odometry reading, when the scan is newer than it.
  const double own_motion =
      options_.max_speed * std::max(0.0, scan->timestamp - odometry_.back().first);
  struct Disk {
    Eigen::Vector2d center;  // in the sensor frame at the scan
    double radius;
  };
  std::vector<Disk> disks;
  // A body seen at `time` at `center` (our robot frame then), carried to the scan by odometry.
  auto add_disk = [&](double time, const Eigen::Vector2d& center, double max_age) {
    const double age = scan->timestamp - time;
    Rigid2d then;
    if (age < 0.0 || age > max_age || !OdometryAt(time, &then)) return;
    const Eigen::Vector2d in_robot = now.inverse() * then * center;
    const double radius = options_.robot_radius + options_.max_speed * age + own_motion;
    disks.push_back({scan->sensor_in_robot.inverse() * in_robot, radius});
  };
  for (const auto& [robot, d] : seen_) add_disk(d.timestamp, d.position_in_observer, options_.max_age);
  for (const auto& [time, center] : laser_bodies_) add_disk(time, center, options_.max_laser_body_age);
  int masked = 0;
  for (int i = 0; i < scan->size(); ++i) {
    if (!scan->IsReturn(i)) continue;
    const double r = scan->ranges[static_cast<size_t>(i)], a = scan->angle(i);
    const Eigen::Vector2d end(r * std::cos(a), r * std::sin(a));
    for (const Disk& disk : disks) {
      if ((end - disk.center).norm() > disk.radius) continue;
      scan->ranges[static_cast<size_t>(i)] = LaserScan::kMasked;
      ++masked;
      break;
    }
  }
  return masked;
}

}  // namespace fleetmap

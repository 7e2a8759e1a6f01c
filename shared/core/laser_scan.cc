#include "shared/core/laser_scan.h"

#include <algorithm>

#include <cmath>

namespace fleetmap {

bool LaserScan::IsReturn(int i) const {
  const float r = ranges[static_cast<size_t>(i)];
  return std::isfinite(r);
}

bool LaserScan::IsMasked(int i) const { return std::isnan(ranges[static_cast<size_t>(i)]); }

int LaserScan::CountReturns() const {
  int count = 0;
  for (float r : ranges) count += std::isfinite(r) ? 1 : 0;
  return count;
}

LaserScan MakeLaserScan(double timestamp, float angle_min, float angle_increment, float range_min,
                        float range_max, const std::vector<float>& raw_ranges,
                        const Rigid2d& sensor_in_robot) {
  LaserScan scan;
  scan.timestamp = timestamp;
  scan.angle_min = angle_min;
  scan.angle_increment = angle_increment;
  scan.range_min = range_min;
  scan.range_max = range_max;
  scan.sensor_in_robot = sensor_in_robot;
  scan.ranges.reserve(raw_ranges.size());
  for (float r : raw_ranges) {
    const bool valid = std::isfinite(r) && r >= range_min && r < range_max && r > 0.0f;
    scan.ranges.push_back(valid ? r : LaserScan::kNoReturn);
  }
  return scan;
}

std::vector<Eigen::Vector2f> ToPointsInSensorFrame(const LaserScan& scan) {
  std::vector<Eigen::Vector2f> points;
  points.reserve(scan.ranges.size());
  for (int i = 0; i < scan.size(); ++i) {
    if (!scan.IsReturn(i)) continue;
    const float a = scan.angle(i);
    const float r = scan.ranges[static_cast<size_t>(i)];
    points.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return points;
}

std::vector<Eigen::Vector2f> ToPointsInRobotFrame(const LaserScan& scan) {
  std::vector<Eigen::Vector2f> points = ToPointsInSensorFrame(scan);
  for (Eigen::Vector2f& p : points) p = scan.sensor_in_robot * p;
  return points;
}

std::vector<Eigen::Vector2f> ReturnsInsideHorizon(const LaserScan& scan, float max_range, float margin) {
  LaserScan inside = scan;
  const float limit = Horizon(scan, max_range) - margin;
  for (float& range : inside.ranges) {
    if (!(range < limit)) range = LaserScan::kNoReturn;
  }
  return ToPointsInRobotFrame(inside);
}

std::vector<Eigen::Vector2f> NoReturnEnds(const LaserScan& scan, float max_range) {
  const float horizon = Horizon(scan, max_range);
  std::vector<Eigen::Vector2f> ends;
  for (int i = 0; i < scan.size(); ++i) {
    if ((scan.IsReturn(i) && scan.ranges[static_cast<size_t>(i)] <= horizon) || scan.IsMasked(i)) continue;
    const double angle = static_cast<double>(scan.angle(i));
    ends.push_back((scan.sensor_in_robot * Eigen::Vector2d(horizon * std::cos(angle), horizon * std::sin(angle)))
                       .cast<float>());
  }
  return ends;
}

float Horizon(const LaserScan& scan, float max_range) {
  return scan.range_max > 0.0f ? std::min(max_range, scan.range_max) : max_range;
}

}  // namespace fleetmap

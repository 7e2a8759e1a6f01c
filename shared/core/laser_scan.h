#ifndef FLEETMAP_SHARED_CORE_LASER_SCAN_H_
#define FLEETMAP_SHARED_CORE_LASER_SCAN_H_

#include <limits>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// A planar laser scan. Beam i points at `angle_min + i * angle_increment` in the sensor frame.
// A beam that saw nothing within range holds kNoReturn, never a number that looks like a range,
// so no caller can mistake "nothing there" for "a wall at max range".
struct LaserScan {
  static constexpr float kNoReturn = std::numeric_limits<float>::infinity();
  // A return taken out on purpose (e.g. one that hit another robot): neither a hit nor free
  // space along the beam. MakeLaserScan never produces it (non-finite input is kNoReturn).
  static constexpr float kMasked = std::numeric_limits<float>::quiet_NaN();

  double timestamp = 0.0;  // seconds
  float angle_min = 0.0f;  // radians
  float angle_increment = 0.0f;
  float range_min = 0.0f;  // metres; readings below it are treated as no-return
  float range_max = 0.0f;  // metres; readings at or above it are no-return
  std::vector<float> ranges;
  // Where the sensor sits on the robot (e.g. fr079's laser is 4 cm behind the robot centre).
  Rigid2d sensor_in_robot;

  int size() const { return static_cast<int>(ranges.size()); }
  float angle(int i) const { return angle_min + static_cast<float>(i) * angle_increment; }
  bool IsReturn(int i) const;
  bool IsMasked(int i) const;
  int CountReturns() const;
  bool HasReturns() const { return CountReturns() > 0; }
};

// Builds a scan from raw readings, turning readings outside [range_min, range_max) and non-finite
// ones into kNoReturn.
LaserScan MakeLaserScan(double timestamp, float angle_min, float angle_increment, float range_min,
                        float range_max, const std::vector<float>& raw_ranges,
                        const Rigid2d& sensor_in_robot = Rigid2d());

// How far the scan can see when its user also caps ranges at `max_range`: the smaller of the
// two (range_max unset, <= 0, counts as no limit of its own).
float Horizon(const LaserScan& scan, float max_range);

// End points of the real returns, in the sensor frame.
std::vector<Eigen::Vector2f> ToPointsInSensorFrame(const LaserScan& scan);
// End points of the real returns, in the robot frame (applies `scan.sensor_in_robot`).
std::vector<Eigen::Vector2f> ToPointsInRobotFrame(const LaserScan& scan);
// ToPointsInRobotFrame of the returns closer than Horizon(scan, max_range) - margin.
std::vector<Eigen::Vector2f> ReturnsInsideHorizon(const LaserScan& scan, float max_range, float margin);
// Where the beams that saw nothing within Horizon(scan, max_range) end, at that horizon (robot
// frame; masked beams left out): the space they crossed counts as seen.
std::vector<Eigen::Vector2f> NoReturnEnds(const LaserScan& scan, float max_range);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_LASER_SCAN_H_

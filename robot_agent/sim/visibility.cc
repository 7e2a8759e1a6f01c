#include "robot_agent/sim/visibility.h"

#include <cmath>

#include "robot_agent/sim/laser_model.h"

namespace fleetmap::sim {

std::vector<VisibilityRecord> ComputeVisibility(double timestamp, const World& world,
                                                const std::vector<Rigid2d>& robots_in_world,
                                                const CameraModel& camera, double body_radius,
                                                double marker_radius) {
  std::vector<VisibilityRecord> records;
  const int count = static_cast<int>(robots_in_world.size());
  const double half_width = 0.5 * camera.options().width;
  for (int i = 0; i < count; ++i) {
    const Rigid2d camera_in_world = robots_in_world[i] * camera.mount();
    for (int j = 0; j < count; ++j) {
      if (i == j) continue;
      VisibilityRecord record;
      record.timestamp = timestamp;
      record.observer = i;
      record.observed = j;
      record.relative = robots_in_world[i].inverse() * robots_in_world[j];
      record.range = record.relative.translation().norm();
      record.bearing = std::atan2(record.relative.y(), record.relative.x());
      const Eigen::Vector2d target = robots_in_world[j].translation();
      const Eigen::Vector2d in_camera = camera_in_world.inverse() * target;
      const double distance = in_camera.norm();
      if (in_camera.x() > 1e-3) {
        const double bearing = std::atan2(in_camera.y(), in_camera.x());
        record.image_u = camera.ColumnOfBearing(bearing);
        const double half_angle = distance > marker_radius ? std::asin(marker_radius / distance)
                                                           : M_PI / 2 - 1e-3;
        record.image_width = camera.ColumnOfBearing(bearing - half_angle) -
                             camera.ColumnOfBearing(bearing + half_angle);
        record.in_camera_fov = std::abs(record.image_u - half_width) <= half_width;
      }
      // The line of sight ends at the marker's surface; walls or other robots before it block.
      const Eigen::Vector2d from = camera_in_world.translation();
      const Eigen::Vector2d direction = (target - from) / std::max(distance, 1e-9);
      const double visible_length = std::max(0.0, distance - marker_radius);
      record.occluded =
          !world.LineOfSight(from, from + visible_length * direction);
      for (int k = 0; k < count && !record.occluded; ++k) {
        if (k == i || k == j) continue;
        record.occluded = RayCircleDistance(from, direction, robots_in_world[k].translation(),
                                            body_radius) < visible_length;
      }
      record.visible = record.in_camera_fov && !record.occluded &&
                       distance <= camera.options().max_depth;
      records.push_back(record);
    }
  }
  return records;
}

}  // namespace fleetmap::sim

#include "shared/matching/seen_from_behind.h"

namespace fleetmap {

SeenFromBehind WallsSeenFromBehind(const std::vector<Eigen::Vector2f>& points_in_robot,
                                   const Eigen::Vector2d& sensor_in_robot, const MatchGrid& grid,
                                   const Rigid2d& robot_in_grid,
                                   const SeenFromBehindOptions& options) {
  SeenFromBehind result;
  const Eigen::Vector2d sensor = robot_in_grid * sensor_in_robot;
  for (const Eigen::Vector2f& p : points_in_robot) {
    const Eigen::Vector2d point = robot_in_grid * Eigen::Vector2d(p.cast<double>());
    if (!grid.Observed(point) || grid.Distance(point) > options.on_wall_distance) continue;
    const double range = (point - sensor).norm();
    if (range <= options.look_back) continue;  // the sensor itself stands in front of the wall
    ++result.on_walls;
    const Eigen::Vector2d in_front = point - (options.look_back / range) * (point - sensor);
    if (!grid.Observed(in_front)) ++result.behind;
  }
  return result;
}

}  // namespace fleetmap

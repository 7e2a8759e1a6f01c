#include "robot_agent/slam/seen_surface_filter.h"

namespace fleetmap {

std::vector<Eigen::Vector2f> PointsOnSeenSurfaces(const std::vector<Eigen::Vector2f>& points,
                                                  const MatchGrid& target, const Rigid2d& pose,
                                                  double max_unseen_distance, double min_kept_share) {
  std::vector<Eigen::Vector2f> kept;
  kept.reserve(points.size());
  for (const Eigen::Vector2f& p : points) {
    const Eigen::Vector2d in_map = pose * Eigen::Vector2d(p.cast<double>());
    if (target.Observed(in_map) || target.Distance(in_map) < max_unseen_distance) kept.push_back(p);
  }
  if (static_cast<double>(kept.size()) < min_kept_share * static_cast<double>(points.size())) return points;
  return kept;
}

}  // namespace fleetmap

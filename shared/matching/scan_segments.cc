#include "shared/matching/scan_segments.h"

#include <cmath>

namespace fleetmap {

std::vector<SurfaceElement> JoinConsecutiveReturns(const std::vector<Eigen::Vector2d>& points_in_beam_order,
                                                   const Eigen::Vector2d& origin,
                                                   const ScanSegmentOptions& options) {
  std::vector<SurfaceElement> segments;
  for (size_t i = 0; i + 1 < points_in_beam_order.size(); ++i) {
    const Eigen::Vector2d& a = points_in_beam_order[i];
    const Eigen::Vector2d& b = points_in_beam_order[i + 1];
    const Eigen::Vector2d between = b - a;
    const double gap = between.norm();
    if (!(gap >= options.min_gap) || gap > options.max_gap) continue;
    const Eigen::Vector2d ray_a = a - origin, ray_b = b - origin;
    const double range = std::min(ray_a.norm(), ray_b.norm());
    const double bearing_step = std::abs(std::atan2(ray_a.x() * ray_b.y() - ray_a.y() * ray_b.x(), ray_a.dot(ray_b)));
    if (!(bearing_step > 0.0) || bearing_step > options.max_bearing_step ||
        bearing_step >= options.min_incidence) {
      continue;
    }
    const double max_gap = range * std::sin(bearing_step) / std::sin(options.min_incidence - bearing_step) +
                           options.range_noise;
    if (gap > max_gap) continue;
    SurfaceElement segment;
    segment.centre = 0.5 * (a + b);
    segment.tangent = between / gap;
    segment.extent_minus = segment.extent_plus = 0.5 * gap;
    segments.push_back(segment);
  }
  return segments;
}

}  // namespace fleetmap

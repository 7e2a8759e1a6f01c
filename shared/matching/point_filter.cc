#include "shared/matching/point_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace fleetmap {

std::vector<Eigen::Vector2f> VoxelFilter(const std::vector<Eigen::Vector2f>& points,
                                         float cell_size) {
  if (!(cell_size > 0.0f)) return points;
  std::unordered_set<uint64_t> seen;
  seen.reserve(points.size() * 2);
  std::vector<Eigen::Vector2f> kept;
  kept.reserve(points.size());
  for (const Eigen::Vector2f& p : points) {
    const float fx = std::floor(p.x() / cell_size), fy = std::floor(p.y() / cell_size);
    if (!(std::abs(fx) < 1e9f && std::abs(fy) < 1e9f)) continue;  // NaN or absurd
    const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(static_cast<int32_t>(fx))) << 32) |
                         static_cast<uint32_t>(static_cast<int32_t>(fy));
    if (seen.insert(key).second) kept.push_back(p);
  }
  return kept;
}

LaserScan ThinBeams(const LaserScan& scan, float min_spacing) {
  LaserScan thinned = scan;
  const float increment = std::abs(scan.angle_increment);
  if (!(min_spacing > 0.0f) || !(increment > 0.0f)) return thinned;
  for (int i = 0; i < scan.size(); ++i) {
    if (!scan.IsReturn(i)) continue;
    float& range = thinned.ranges[static_cast<size_t>(i)];
    const float stride = std::floor(min_spacing / (range * increment));
    if (stride >= 2.0f && i % static_cast<int>(std::min(stride, 1e6f)) != 0) range = LaserScan::kNoReturn;
  }
  return thinned;
}

std::vector<Eigen::Vector2f> RangeFilter(const std::vector<Eigen::Vector2f>& points,
                                         float max_range) {
  std::vector<Eigen::Vector2f> kept;
  kept.reserve(points.size());
  for (const Eigen::Vector2f& p : points) {
    if (p.squaredNorm() <= max_range * max_range) kept.push_back(p);
  }
  return kept;
}

}  // namespace fleetmap

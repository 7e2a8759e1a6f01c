#include "robot_agent/slam/small_foreground_objects.h"

#include <cmath>

namespace fleetmap {

std::vector<bool> SmallForegroundObjects(const std::vector<Eigen::Vector2f>& points,
                                         const SmallForegroundObjectOptions& options) {
  const std::vector<int> ids = SmallForegroundObjectIds(points, options);
  std::vector<bool> small(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) small[i] = ids[i] >= 0;
  return small;
}

std::vector<int> SmallForegroundObjectIds(const std::vector<Eigen::Vector2f>& points,
                                          const SmallForegroundObjectOptions& options) {
  const size_t n = points.size();
  std::vector<int> ids(n, -1);
  if (n == 0) return ids;
  int objects = 0;
  auto range = [&](size_t i) { return static_cast<double>(points[i].norm()); };
  auto bearing = [&](size_t i) { return std::atan2(static_cast<double>(points[i].y()), static_cast<double>(points[i].x())); };
  // Whether returns i and i + 1 lie on one object.
  auto joined = [&](size_t i) {
    return std::abs(range(i + 1) - range(i)) <= options.depth_jump &&
           std::abs(bearing(i + 1) - bearing(i)) <= options.max_bearing_step;
  };
  // Whether the neighbour of run end `end` across the break (index `other`, or none) is farther.
  auto behind = [&](size_t end, long other) {
    if (other < 0 || other >= static_cast<long>(n)) return true;
    const size_t o = static_cast<size_t>(other);
    if (std::abs(bearing(o) - bearing(end)) > options.max_bearing_step) return true;
    return range(o) > range(end) + options.depth_jump;
  };
  size_t begin = 0;
  for (size_t i = 0; i < n; ++i) {
    if (i + 1 < n && joined(i)) continue;
    const size_t last = i;  // run [begin, last]
    const bool compact = (points[last] - points[begin]).norm() <= options.max_size;
    if (compact && behind(begin, static_cast<long>(begin) - 1) && behind(last, static_cast<long>(last) + 1)) {
      for (size_t k = begin; k <= last; ++k) ids[k] = objects;
      ++objects;
    }
    begin = i + 1;
  }
  return ids;
}

}  // namespace fleetmap

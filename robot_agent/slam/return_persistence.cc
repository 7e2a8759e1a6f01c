#include "robot_agent/slam/return_persistence.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetmap {
namespace {

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

ReturnPersistence::ReturnPersistence(const ReturnPersistenceOptions& options) : options_(options) {}

uint64_t ReturnPersistence::Key(int64_t x, int64_t y) {
  // Offset so that the order of keys follows x, then y, across 0.
  const auto biased = [](int64_t v) {
    return static_cast<uint32_t>(static_cast<uint64_t>(v) + (uint64_t{1} << 31));
  };
  return (static_cast<uint64_t>(biased(x)) << 32) | biased(y);
}

double ReturnPersistence::Distance(const Eigen::Vector2d& point) const {
  const double cell = options_.max_join;
  const int64_t cx = static_cast<int64_t>(std::floor(point.x() / cell));
  const int64_t cy = static_cast<int64_t>(std::floor(point.y() / cell));
  double best = std::numeric_limits<double>::infinity();
  for (int64_t dx = -1; dx <= 1; ++dx) {
    const uint64_t last = Key(cx + dx, cy + 1);
    auto it = std::lower_bound(cells_.begin(), cells_.end(),
                               std::make_pair(Key(cx + dx, cy - 1), uint32_t{0}));
    for (; it != cells_.end() && it->first <= last; ++it) {
      const Segment& s = segments_[it->second];
      best = std::min(best, SegmentDistance(point, s.a, s.b));
    }
  }
  return best;
}

void ReturnPersistence::Add(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const uint32_t index = static_cast<uint32_t>(segments_.size());
  segments_.push_back({a, b});
  // In the cell of every point along it, one cell apart at most, which is where Distance looks.
  const double cell = options_.max_join;
  const int steps = static_cast<int>(std::ceil((b - a).norm() / cell));
  uint64_t last = 0;
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2d p = a + (b - a) * (steps > 0 ? static_cast<double>(k) / steps : 0.0);
    const uint64_t key = Key(static_cast<int64_t>(std::floor(p.x() / cell)), static_cast<int64_t>(std::floor(p.y() / cell)));
    if (k > 0 && key == last) continue;
    cells_.emplace_back(key, index);
    last = key;
  }
}

std::vector<bool> ReturnPersistence::Persisted(const std::vector<Eigen::Vector2d>& points) const {
  const bool pass_all = first_call_ || !(options_.tolerance > 0.0);
  std::vector<bool> persisted(points.size(), pass_all);
  if (!pass_all) {
    for (size_t i = 0; i < points.size(); ++i) {
      persisted[i] = points[i].allFinite() && Distance(points[i]) <= options_.tolerance;
    }
  }
  return persisted;
}

std::vector<bool> ReturnPersistence::Observe(const std::vector<Eigen::Vector2d>& points,
                                             const Eigen::Vector2d& origin) {
  const std::vector<bool> persisted = Persisted(points);
  first_call_ = false;
  // This scan's surface, for the next: each return, joined to the next one when they are close
  // or on one surface.
  segments_.clear();
  cells_.clear();
  std::vector<Eigen::Vector2d> finite;
  finite.reserve(points.size());
  for (const Eigen::Vector2d& p : points) {
    if (p.allFinite()) finite.push_back(p);
  }
  for (size_t i = 0; i < finite.size(); ++i) {
    Add(finite[i], finite[i]);
    if (i + 1 < finite.size() && (finite[i + 1] - finite[i]).norm() <= options_.max_join) Add(finite[i], finite[i + 1]);
  }
  for (const SurfaceElement& joined : JoinConsecutiveReturns(finite, origin, options_.segments)) {
    Add(joined.centre - joined.extent_minus * joined.tangent, joined.centre + joined.extent_plus * joined.tangent);
  }
  std::sort(cells_.begin(), cells_.end());
  return persisted;
}

}  // namespace fleetmap

#include "map_server/merge/grid_points.h"

#include <cmath>
#include <unordered_set>

namespace fleetmap {

std::vector<Eigen::Vector2d> OccupiedPoints(const OccupancyGrid& grid, float occupied_log_odds,
                                            const Rigid2d& grid_to_frame) {
  std::vector<Eigen::Vector2d> points;
  const std::vector<float>& cells = grid.log_odds();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (cells[static_cast<size_t>(y) * grid.width() + x] > occupied_log_odds) {
        points.push_back(grid_to_frame * grid.CellCenter(CellIndex(x, y)));
      }
    }
  }
  return points;
}

std::vector<Eigen::Vector2d> VoxelFilter(const std::vector<Eigen::Vector2d>& points,
                                         double cell_size, size_t max_points) {
  std::vector<Eigen::Vector2d> kept;
  std::unordered_set<int64_t> seen;
  for (const Eigen::Vector2d& p : points) {
    const int64_t x = static_cast<int64_t>(std::floor(p.x() / cell_size));
    const int64_t y = static_cast<int64_t>(std::floor(p.y() / cell_size));
    if (seen.insert((x << 32) ^ (y & 0xffffffff)).second) kept.push_back(p);
  }
  if (max_points == 0 || kept.size() <= max_points) return kept;
  std::vector<Eigen::Vector2d> thinned;
  thinned.reserve(max_points);
  const double stride = static_cast<double>(kept.size()) / static_cast<double>(max_points);
  for (size_t i = 0; i < max_points; ++i) thinned.push_back(kept[static_cast<size_t>(i * stride)]);
  return thinned;
}

Eigen::Vector2d Centroid(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) sum += p;
  return points.empty() ? sum : Eigen::Vector2d(sum / static_cast<double>(points.size()));
}

}  // namespace fleetmap

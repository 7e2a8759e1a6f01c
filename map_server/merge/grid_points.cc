#include "map_server/merge/grid_points.h"

#include <algorithm>
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

Eigen::Vector2d WallNormalAt(const OccupancyGrid& grid, const CellIndex& cell,
                             float free_log_odds) {
  constexpr int kReach = 2;  // cells
  // A wall seen from one side has all its free neighbours there: their unit directions add up
  // to well over this share of their count; seen from both sides they cancel.
  constexpr double kOneSided = 0.3;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int free = 0;
  for (int dy = -kReach; dy <= kReach; ++dy) {
    for (int dx = -kReach; dx <= kReach; ++dx) {
      if ((dx == 0 && dy == 0) || grid.LogOdds(cell + CellIndex(dx, dy)) >= free_log_odds) continue;
      sum += Eigen::Vector2d(dx, dy).normalized();
      ++free;
    }
  }
  return free > 0 && sum.norm() > kOneSided * free ? Eigen::Vector2d(sum.normalized())
                                                   : Eigen::Vector2d::Zero();
}

std::vector<Eigen::Vector2d> WallNormals(const OccupancyGrid& grid, float occupied_log_odds,
                                         float free_log_odds, const Rigid2d& grid_to_frame) {
  std::vector<Eigen::Vector2d> normals;
  const Eigen::Matrix2d r = grid_to_frame.rotation_matrix();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const CellIndex cell(x, y);
      if (grid.LogOdds(cell) > occupied_log_odds) {
        normals.push_back(r * WallNormalAt(grid, cell, free_log_odds));
      }
    }
  }
  return normals;
}

std::vector<size_t> VoxelFilterIndices(const std::vector<Eigen::Vector2d>& points,
                                       double cell_size, size_t max_points) {
  std::vector<size_t> kept;
  std::unordered_set<int64_t> seen;
  for (size_t i = 0; i < points.size(); ++i) {
    const int64_t x = static_cast<int64_t>(std::floor(points[i].x() / cell_size));
    const int64_t y = static_cast<int64_t>(std::floor(points[i].y() / cell_size));
    if (seen.insert((x << 32) ^ (y & 0xffffffff)).second) kept.push_back(i);
  }
  if (max_points == 0 || kept.size() <= max_points) return kept;
  std::vector<size_t> thinned;
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

double Radius(const std::vector<Eigen::Vector2d>& points) {
  double radius = 0.0;
  for (const Eigen::Vector2d& p : points) radius = std::max(radius, p.norm());
  return radius;
}

}  // namespace fleetmap

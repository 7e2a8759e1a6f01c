#include "map_server/merge/trail_walls.h"

#include <cmath>

namespace fleetmap {

TrailMask::TrailMask(const std::vector<Eigen::Vector2d>& positions, double radius,
                     double resolution)
    : resolution_(resolution) {
  if (positions.empty() || !(resolution > 0.0) || !(radius >= 0.0)) return;
  Eigen::Vector2d min = positions.front(), max = positions.front();
  for (const Eigen::Vector2d& p : positions) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  const int reach = static_cast<int>(std::ceil(radius / resolution)) + 1;
  origin_ = min - Eigen::Vector2d::Constant(reach * resolution);
  width_ = static_cast<int>(std::ceil((max.x() - min.x()) / resolution)) + 2 * reach + 1;
  height_ = static_cast<int>(std::ceil((max.y() - min.y()) / resolution)) + 2 * reach + 1;
  cells_.assign(static_cast<size_t>(width_) * height_, false);
  const double radius_squared = radius * radius;
  for (const Eigen::Vector2d& p : positions) {
    const Eigen::Vector2d c = (p - origin_) / resolution;
    const int cx = static_cast<int>(std::floor(c.x())), cy = static_cast<int>(std::floor(c.y()));
    for (int y = cy - reach; y <= cy + reach; ++y) {
      for (int x = cx - reach; x <= cx + reach; ++x) {
        if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
        const Eigen::Vector2d center = origin_ + resolution * Eigen::Vector2d(x + 0.5, y + 0.5);
        if ((center - p).squaredNorm() <= radius_squared) {
          cells_[static_cast<size_t>(y) * width_ + x] = true;
        }
      }
    }
  }
}

bool TrailMask::Contains(const Eigen::Vector2d& point) const {
  if (cells_.empty()) return false;
  const Eigen::Vector2d c = (point - origin_) / resolution_;
  const int x = static_cast<int>(std::floor(c.x())), y = static_cast<int>(std::floor(c.y()));
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
  return cells_[static_cast<size_t>(y) * width_ + x];
}

WallBlobs::WallBlobs(const OccupancyGrid& grid, float occupied_log_odds)
    : origin_(grid.origin()),
      resolution_(grid.resolution()),
      width_(grid.width()),
      height_(grid.height()) {
  const int width = grid.width(), height = grid.height();
  const std::vector<float>& cells = grid.log_odds();
  label_.assign(cells.size(), -1);
  std::vector<int> stack;
  for (int start = 0; start < static_cast<int>(cells.size()); ++start) {
    if (label_[start] >= 0 || !(cells[start] > occupied_log_odds)) continue;
    const int blob = size();
    blob_cells_.emplace_back();
    label_[start] = blob;
    stack.push_back(start);
    while (!stack.empty()) {
      const int index = stack.back();
      stack.pop_back();
      const int x = index % width, y = index / width;
      blob_cells_.back().push_back(grid.CellCenter(CellIndex(x, y)));
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const int next = ny * width + nx;
          if (label_[next] >= 0 || !(cells[next] > occupied_log_odds)) continue;
          label_[next] = blob;
          stack.push_back(next);
        }
      }
    }
  }
}

int WallBlobs::BlobAt(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d c = (point - origin_) / resolution_;
  const int x = static_cast<int>(std::floor(c.x())), y = static_cast<int>(std::floor(c.y()));
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return -1;
  return label_[static_cast<size_t>(y) * width_ + x];
}

std::vector<bool> WallBlobs::OnTrails(const TrailMask& trails,
                                      const Rigid2d& grid_to_trails) const {
  std::vector<bool> on(blob_cells_.size(), true);
  for (size_t blob = 0; blob < blob_cells_.size(); ++blob) {
    for (const Eigen::Vector2d& center : blob_cells_[blob]) {
      if (!trails.Contains(grid_to_trails * center)) {
        on[blob] = false;
        break;
      }
    }
  }
  return on;
}

}  // namespace fleetmap

#include "robot_agent/localization/free_space.h"

#include <cmath>

namespace fleetmap {

FreeSpace FreeSpace::FromGrid(const OccupancyGrid& grid, float free_probability) {
  FreeSpace space;
  space.resolution_ = grid.resolution();
  space.width_ = grid.width();
  space.height_ = grid.height();
  space.min_ = grid.origin();
  space.max_ = grid.origin() + grid.resolution() * Eigen::Vector2d(grid.width(), grid.height());
  space.free_mask_.assign(static_cast<size_t>(grid.width()) * grid.height(), 0);
  const float threshold = ProbabilityToLogOdds(free_probability);
  const std::vector<float>& cells = grid.log_odds();
  for (size_t i = 0; i < cells.size(); ++i) {
    // Unknown cells (log-odds exactly 0) are never free: nobody has been there.
    if (cells[i] < threshold && cells[i] != 0.0f) {
      space.free_mask_[i] = 1;
      space.free_cells_.push_back(static_cast<int32_t>(i));
    }
  }
  space.area_ = static_cast<double>(space.free_cells_.size()) * grid.resolution() *
                grid.resolution();
  return space;
}

FreeSpace FreeSpace::FromBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max) {
  FreeSpace space;
  space.is_box_ = true;
  space.min_ = min.cwiseMin(max);
  space.max_ = max.cwiseMax(min);
  const Eigen::Vector2d size = space.max_ - space.min_;
  space.area_ = size.x() * size.y();
  return space;
}

bool FreeSpace::IsFree(const Eigen::Vector2d& point) const {
  if (is_box_) {
    return (point.array() >= min_.array()).all() && (point.array() <= max_.array()).all();
  }
  const int x = static_cast<int>(std::floor((point.x() - min_.x()) / resolution_));
  const int y = static_cast<int>(std::floor((point.y() - min_.y()) / resolution_));
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
  return free_mask_[static_cast<size_t>(y) * width_ + x] != 0;
}

Eigen::Vector2d FreeSpace::SamplePoint(std::mt19937& rng) const {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  if (is_box_) {
    return min_ + (max_ - min_).cwiseProduct(Eigen::Vector2d(unit(rng), unit(rng)));
  }
  if (free_cells_.empty()) return 0.5 * (min_ + max_);
  std::uniform_int_distribution<size_t> pick(0, free_cells_.size() - 1);
  const int32_t index = free_cells_[pick(rng)];
  const int x = index % width_;
  const int y = index / width_;
  return min_ + resolution_ * Eigen::Vector2d(x + unit(rng), y + unit(rng));
}

}  // namespace fleetmap

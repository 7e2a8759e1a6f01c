#include "map_server/merge/score_grid.h"

#include <algorithm>
#include <cmath>

#include "shared/core/likelihood_field.h"

namespace fleetmap {

ScoreGrid::ScoreGrid(const OccupancyGrid& target, const ScoreGridOptions& options)
    : resolution_(options.resolution), unknown_score_(options.unknown_score) {
  CellIndex min_cell, max_cell;
  if (!target.KnownBounds(&min_cell, &max_cell)) return;
  const double sigma = options.sigma > 0.0 ? options.sigma : options.resolution;
  const double max_distance = 3.0 * sigma;
  const int margin = static_cast<int>(std::ceil(max_distance / resolution_)) + 1;
  const Eigen::Vector2d lo = target.CellCenter(min_cell);
  const Eigen::Vector2d hi = target.CellCenter(max_cell);
  origin_ = (lo / resolution_).array().floor().matrix() * resolution_ -
            Eigen::Vector2d::Constant(margin * resolution_);
  width_ = static_cast<int>(std::floor((hi.x() - origin_.x()) / resolution_)) + 1 + margin;
  height_ = static_cast<int>(std::floor((hi.y() - origin_.y()) / resolution_)) + 1 + margin;
  const size_t size = static_cast<size_t>(width_) * static_cast<size_t>(height_);

  // Aggregate the (usually finer) target into search cells: a search cell is a wall when any
  // target cell inside it is, so thin walls survive the coarser grid.
  std::vector<int8_t> state(size, 0);  // 1 wall, -1 free, 0 unknown
  for (int y = min_cell.y(); y <= max_cell.y(); ++y) {
    for (int x = min_cell.x(); x <= max_cell.x(); ++x) {
      const float l = target.LogOdds(CellIndex(x, y));
      if (l == 0.0f) continue;
      const Eigen::Vector2d c = (target.CellCenter(CellIndex(x, y)) - origin_) / resolution_;
      const int cx = static_cast<int>(std::floor(c.x())), cy = static_cast<int>(std::floor(c.y()));
      if (cx < 0 || cy < 0 || cx >= width_ || cy >= height_) continue;
      int8_t& s = state[static_cast<size_t>(cy) * width_ + cx];
      if (l > options.occupied_log_odds) {
        s = 1;
      } else if (l < options.free_log_odds && s == 0) {
        s = -1;
      }
    }
  }

  OccupancyGrid walls(OccupancyGridOptions{resolution_}, origin_, width_, height_);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (state[static_cast<size_t>(y) * width_ + x] == 1) {
        walls.SetLogOdds(CellIndex(x, y), 4.0f);
        ++num_occupied_;
      }
    }
  }
  LikelihoodFieldOptions field_options;
  field_options.max_distance = max_distance;
  const LikelihoodField field(walls, field_options);
  // The field adds its own margin around the grid; find where our cell (0, 0) sits in it.
  const int offset = static_cast<int>(std::lround((origin_.x() - field.origin().x()) / resolution_));

  values_.assign(size, 0.0f);
  known_.assign(size, 0);
  const double inv_two_sigma2 = 1.0 / (2.0 * sigma * sigma);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t i = static_cast<size_t>(y) * width_ + x;
      known_[i] = state[i] != 0;
      const double d = field.CellDistance(x + offset, y + offset);
      if (d < 2.0 * sigma) {
        values_[i] = static_cast<float>(std::exp(-d * d * inv_two_sigma2));
      } else if (state[i] == -1) {
        values_[i] = options.free_penalty;
      } else if (state[i] == 0) {
        values_[i] = unknown_score_;
      }
    }
  }
}

ScoreGridPyramid::ScoreGridPyramid(const ScoreGrid& base, int levels) : base_(base) {
  levels_.resize(static_cast<size_t>(std::max(1, levels)));
  Level& zero = levels_[0];
  zero.width = base.width();
  zero.height = base.height();
  for (int h = 1; h < static_cast<int>(levels_.size()); ++h) {
    Level& level = levels_[static_cast<size_t>(h)];
    const int half = 1 << (h - 1);
    level.pad = (1 << h) - 1;
    level.width = base.width() + level.pad;
    level.height = base.height() + level.pad;
    level.values.assign(static_cast<size_t>(level.width) * level.height, 0.0f);
    // max over [x, x + 2^h) = max(M_{h-1}(x), M_{h-1}(x + 2^{h-1})), separably in x and y.
    for (int y = -level.pad; y < base.height(); ++y) {
      for (int x = -level.pad; x < base.width(); ++x) {
        const float a = std::max(Value(h - 1, x, y), Value(h - 1, x + half, y));
        const float b = std::max(Value(h - 1, x, y + half), Value(h - 1, x + half, y + half));
        level.values[static_cast<size_t>(y + level.pad) * level.width + (x + level.pad)] =
            std::max(a, b);
      }
    }
  }
}

float ScoreGridPyramid::Value(int level, int x, int y) const {
  if (level == 0) return base_.Value(x, y);
  const Level& l = levels_[static_cast<size_t>(level)];
  const int ix = x + l.pad, iy = y + l.pad;
  if (ix < 0 || iy < 0 || ix >= l.width || iy >= l.height) return base_.unknown_score();
  return l.values[static_cast<size_t>(iy) * l.width + ix];
}

}  // namespace fleetmap

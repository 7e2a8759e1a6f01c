#ifndef FLEETMAP_MAP_SERVER_MERGE_SCORE_GRID_H_
#define FLEETMAP_MAP_SERVER_MERGE_SCORE_GRID_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"

namespace fleetmap {

struct ScoreGridOptions {
  double resolution = 0.1;        // metres per cell of the search grid
  float occupied_log_odds = 0.4f;  // source cells above this count as walls (p ~ 0.6)
  float free_log_odds = -0.4f;     // source cells below this count as seen free
  // A wall point scores exp(-d^2 / 2 sigma^2) at distance d from the nearest target wall;
  // sigma defaults to the resolution so that rounding to the grid costs little.
  double sigma = 0.0;
  // A wall point landing in seen-free space far from any wall scores this (<= 0). It is what
  // makes a wrong alignment that pushes walls through corridors lose against the true one.
  float free_penalty = -0.5f;
  // A wall point landing where the target saw nothing (inside its bounds or beyond) scores
  // this. 0 for matching: only walls seen by both count. Above 0 it orders a search by how
  // consistent an alignment is where the maps do overlap, over how much of them overlaps.
  float unknown_score = 0.0f;
};

// The scoring surface of the correlative matcher: a dense grid of per-cell scores built from a
// target occupancy grid, read at integer cells. Unknown space scores options.unknown_score.
class ScoreGrid {
 public:
  ScoreGrid() = default;
  ScoreGrid(const OccupancyGrid& target, const ScoreGridOptions& options);

  double resolution() const { return resolution_; }
  const Eigen::Vector2d& origin() const { return origin_; }  // lower-left of cell (0, 0)
  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0 || height_ == 0; }
  int num_occupied() const { return num_occupied_; }
  float unknown_score() const { return unknown_score_; }

  float Value(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return unknown_score_;
    return values_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)];
  }
  // True when the cell was observed (free or occupied) in the target.
  bool Known(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
    return known_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)] != 0;
  }
  Eigen::Vector2d ToCellCoordinates(const Eigen::Vector2d& point) const {
    return (point - origin_) / resolution_;
  }

 private:
  double resolution_ = 0.1;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  int num_occupied_ = 0;
  float unknown_score_ = 0.0f;
  std::vector<float> values_;
  std::vector<uint8_t> known_;
};

// Max-pooled copies of a ScoreGrid for branch and bound: level h holds, for every cell x, the
// maximum of the base grid over [x, x + 2^h) x [y, y + 2^h). Reading a level therefore bounds
// every translation in a 2^h x 2^h block of the search window from above.
class ScoreGridPyramid {
 public:
  ScoreGridPyramid(const ScoreGrid& base, int levels);

  int levels() const { return static_cast<int>(levels_.size()); }
  const ScoreGrid& base() const { return base_; }
  // Level 0 is the base grid.
  float Value(int level, int x, int y) const;

 private:
  struct Level {
    int pad = 0;  // the level covers x in [-pad, width)
    int width = 0;
    int height = 0;
    std::vector<float> values;
  };
  const ScoreGrid& base_;
  std::vector<Level> levels_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_SCORE_GRID_H_

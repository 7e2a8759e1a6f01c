#ifndef FLEETMAP_SHARED_MATCHING_MATCH_GRID_PYRAMID_H_
#define FLEETMAP_SHARED_MATCHING_MATCH_GRID_PYRAMID_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "shared/matching/match_grid.h"

namespace fleetmap {

// Max-pooled score grids for branch-and-bound search. Level d answers "what is the best score
// any translation in a block of 2^d x 2^d cells could give this point", so a whole block of
// candidate translations is bounded by one lookup per point. Scores are stored as bytes
// (score * 255): pooling commutes with the monotone quantisation, so bounds stay valid.
// Build it once per target map (e.g. per finished submap) and reuse it for every search.
class MatchGridPyramid {
 public:
  MatchGridPyramid(const MatchGrid& grid, int levels = 7);

  int levels() const { return static_cast<int>(levels_.size()); }
  double resolution() const { return resolution_; }
  const Eigen::Vector2d& origin() const { return origin_; }  // of base cell (0, 0)
  int base_width() const { return base_width_; }
  int base_height() const { return base_height_; }

  // Best quantised score over base cells [x, x + 2^level) x [y, y + 2^level); 0 off the grid.
  int BlockScore(int level, int x, int y) const {
    const Level& l = levels_[static_cast<size_t>(level)];
    const int ix = x + l.offset, iy = y + l.offset;
    if (ix < 0 || iy < 0 || ix >= l.width || iy >= l.height) return 0;
    return l.cells[static_cast<size_t>(iy) * static_cast<size_t>(l.width) + static_cast<size_t>(ix)];
  }

 private:
  struct Level {
    int width = 0;
    int height = 0;
    int offset = 0;  // 2^level - 1: a block starting at base x is stored at x + offset
    std::vector<uint8_t> cells;
  };

  double resolution_ = 0.05;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int base_width_ = 0;
  int base_height_ = 0;
  std::vector<Level> levels_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_MATCH_GRID_PYRAMID_H_

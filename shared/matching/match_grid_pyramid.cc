#include "shared/matching/match_grid_pyramid.h"

#include <algorithm>

namespace fleetmap {

MatchGridPyramid::MatchGridPyramid(const MatchGrid& grid, int levels)
    : resolution_(grid.resolution()),
      origin_(grid.origin()),
      base_width_(grid.width()),
      base_height_(grid.height()) {
  levels = std::clamp(levels, 1, 16);
  Level base;
  base.width = base_width_;
  base.height = base_height_;
  base.cells.resize(static_cast<size_t>(base.width) * static_cast<size_t>(base.height));
  for (int y = 0; y < base.height; ++y) {
    for (int x = 0; x < base.width; ++x) {
      base.cells[static_cast<size_t>(y) * static_cast<size_t>(base.width) + static_cast<size_t>(x)] =
          static_cast<uint8_t>(255.0f * grid.CellScore(x, y) + 0.5f);
    }
  }
  levels_.push_back(std::move(base));
  // Doubling: the block [i - 2k + 1, i] is the union of [i - k + 1, i] and [i - 2k + 1, i - k],
  // so each level is the max of two shifted copies of the previous one, first along x, then y.
  for (int d = 1; d < levels; ++d) {
    const Level& prev = levels_.back();
    const int half = 1 << (d - 1);
    Level next;
    next.width = prev.width + half;
    next.height = prev.height + half;
    next.offset = (1 << d) - 1;
    std::vector<uint8_t> along_x(static_cast<size_t>(next.width) * static_cast<size_t>(prev.height), 0);
    for (int y = 0; y < prev.height; ++y) {
      const uint8_t* src = prev.cells.data() + static_cast<size_t>(y) * static_cast<size_t>(prev.width);
      uint8_t* dst = along_x.data() + static_cast<size_t>(y) * static_cast<size_t>(next.width);
      for (int x = 0; x < next.width; ++x) {
        const uint8_t a = x < prev.width ? src[x] : 0;
        const uint8_t b = x - half >= 0 && x - half < prev.width ? src[x - half] : 0;
        dst[x] = std::max(a, b);
      }
    }
    next.cells.assign(static_cast<size_t>(next.width) * static_cast<size_t>(next.height), 0);
    for (int y = 0; y < next.height; ++y) {
      uint8_t* dst = next.cells.data() + static_cast<size_t>(y) * static_cast<size_t>(next.width);
      const bool has_a = y < prev.height;
      const bool has_b = y - half >= 0 && y - half < prev.height;
      const uint8_t* a = has_a ? along_x.data() + static_cast<size_t>(y) * static_cast<size_t>(next.width) : nullptr;
      const uint8_t* b = has_b ? along_x.data() + static_cast<size_t>(y - half) * static_cast<size_t>(next.width) : nullptr;
      for (int x = 0; x < next.width; ++x) {
        dst[x] = std::max(has_a ? a[x] : uint8_t{0}, has_b ? b[x] : uint8_t{0});
      }
    }
    levels_.push_back(std::move(next));
  }
}

}  // namespace fleetmap

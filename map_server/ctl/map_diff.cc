#include "map_server/ctl/map_diff.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

enum CellClass { kUnknown, kFree, kOccupied };

// Log-odds beyond +-0.4 (p outside [0.4, 0.6]) decide the class; the rest is unknown.
CellClass Classify(const QuantizedGrid& grid, int x, int y) {
  if (x < 0 || y < 0 || x >= grid.geometry.width || y >= grid.geometry.height) return kUnknown;
  const float log_odds =
      grid.cells[static_cast<size_t>(y) * grid.geometry.width + x] * grid.log_odds_scale;
  if (log_odds > 0.4f) return kOccupied;
  if (log_odds < -0.4f) return kFree;
  return kUnknown;
}

}  // namespace

MapDiff DiffMaps(const QuantizedGrid& before, const QuantizedGrid& after) {
  MapDiff diff;
  const double r = before.geometry.resolution;
  // `after`'s cell (0, 0) sits at `offset` in `before`'s cell coordinates.
  const Eigen::Vector2d shift = (after.geometry.origin - before.geometry.origin) / r;
  const int ox = static_cast<int>(std::lround(shift.x()));
  const int oy = static_cast<int>(std::lround(shift.y()));
  const int x0 = std::min(0, ox), y0 = std::min(0, oy);
  const int x1 = std::max(before.geometry.width, ox + after.geometry.width);
  const int y1 = std::max(before.geometry.height, oy + after.geometry.height);
  diff.width = std::max(0, x1 - x0);
  diff.height = std::max(0, y1 - y0);
  diff.cells_compared = static_cast<int64_t>(diff.width) * diff.height;
  diff.rgb.assign(static_cast<size_t>(diff.cells_compared) * 3, 0);
  for (int y = y0; y < y1; ++y) {
    const int row = y1 - 1 - y;  // images go top-down
    for (int x = x0; x < x1; ++x) {
      const CellClass a = Classify(before, x, y);
      const CellClass b = Classify(after, x - ox, y - oy);
      uint8_t* pixel = &diff.rgb[(static_cast<size_t>(row) * diff.width + (x - x0)) * 3];
      if (a == b) {
        const uint8_t grey = b == kOccupied ? 120 : b == kFree ? 250 : 215;
        pixel[0] = pixel[1] = pixel[2] = grey;
        continue;
      }
      ++diff.changed;
      if (b == kOccupied) {
        ++diff.became_occupied;
        pixel[0] = 230;
      } else if (b == kFree) {
        ++diff.became_free;
        pixel[1] = 180;
      } else {
        ++diff.became_unknown;
        pixel[2] = 230;
      }
    }
  }
  return diff;
}

}  // namespace fleetmap

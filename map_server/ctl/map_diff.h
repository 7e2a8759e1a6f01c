#ifndef FLEETMAP_MAP_SERVER_CTL_MAP_DIFF_H_
#define FLEETMAP_MAP_SERVER_CTL_MAP_DIFF_H_

#include <cstdint>
#include <vector>

#include "shared/codec/grid_codec.h"

namespace fleetmap {

// Cells whose class (free / occupied / unknown) differs between two versions of a map, and an
// RGB picture of the differences (row 0 at the top): unchanged cells in pale grey tones, cells
// that became occupied red, became free green, became unknown blue.
struct MapDiff {
  int64_t cells_compared = 0;  // cells of the union of both extents
  int64_t changed = 0;
  int64_t became_occupied = 0;
  int64_t became_free = 0;
  int64_t became_unknown = 0;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};

// Both grids must have the same resolution; their origins may differ (aligned to whole cells).
// Pure.
MapDiff DiffMaps(const QuantizedGrid& before, const QuantizedGrid& after);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_CTL_MAP_DIFF_H_

#include "robot_agent/slam/packed_submap.h"

#include <cassert>
#include <cstring>
#include <utility>
#include <vector>

#include "shared/codec/zstd_codec.h"

namespace fleetmap {

PackedSubmap PackSubmap(Submap submap) {
  PackedSubmap packed;
  const OccupancyGrid& grid = submap.grid;
  packed.grid_options = grid.options();
  packed.grid_origin = grid.origin();
  packed.grid_width = grid.width();
  packed.grid_height = grid.height();
  packed.compressed_cells =
      ZstdCompress(grid.log_odds().data(), grid.log_odds().size() * sizeof(float));
  submap.grid = OccupancyGrid(packed.grid_options);
  packed.header = std::move(submap);
  return packed;
}

Submap UnpackSubmap(const PackedSubmap& packed) {
  Submap submap = packed.header;
  submap.grid = OccupancyGrid(packed.grid_options, packed.grid_origin, packed.grid_width,
                              packed.grid_height);
  const size_t cells = static_cast<size_t>(packed.grid_width) * static_cast<size_t>(packed.grid_height);
  std::string bytes, error;
  // Our own frame from PackSubmap, never data from outside: failing is a bug.
  const bool ok = ZstdDecompress(packed.compressed_cells, cells * sizeof(float), &bytes, &error);
  assert(ok && "a packed submap's cells do not decompress");
  (void)ok;
  std::vector<float> values(cells);
  std::memcpy(values.data(), bytes.data(), bytes.size());
  for (int y = 0; y < packed.grid_height; ++y) {
    for (int x = 0; x < packed.grid_width; ++x) {
      const float value = values[static_cast<size_t>(y) * static_cast<size_t>(packed.grid_width) + static_cast<size_t>(x)];
      if (value != 0.0f) submap.grid.SetLogOdds(CellIndex(x, y), value);
    }
  }
  return submap;
}

}  // namespace fleetmap

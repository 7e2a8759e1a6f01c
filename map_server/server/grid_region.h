#ifndef FLEETMAP_MAP_SERVER_SERVER_GRID_REGION_H_
#define FLEETMAP_MAP_SERVER_SERVER_GRID_REGION_H_

#include <optional>
#include <string>

#include <Eigen/Core>

#include "shared/codec/grid_codec.h"

namespace fleetmap {

struct RegionQuery {
  // Axis-aligned box (min, max) in the map frame; unset = the whole map.
  std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> box;
  double resolution = 0.0;  // metres per cell; 0 = the map's own
  int64_t max_cells = 64LL << 20;
};

enum class RegionError { kNone, kInvalid, kTooLarge };

// Cuts a box out of `map` and resamples it. Coarser cells keep "occupied wins, then free, then
// unknown" over the cells they cover; finer cells take the cell under their centre. The answer
// is clipped to the map (a box outside it gives an empty grid). Pure.
bool ExtractRegion(const QuantizedGrid& map, const RegionQuery& query, QuantizedGrid* region,
                   RegionError* code, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_GRID_REGION_H_

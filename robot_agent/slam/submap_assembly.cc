#include "robot_agent/slam/submap_assembly.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

OccupancyGrid AssembleSubmaps(const std::vector<const Submap*>& submaps,
                              const OccupancyGridOptions& options) {
  OccupancyGrid grid(options);
  for (const Submap* submap : submaps) {
    if (submap != nullptr) AddSubmapToAssembly(*submap, &grid);
  }
  return grid;
}

void AddSubmapToAssembly(const Submap& submap, OccupancyGrid* grid) {
  CellIndex lo, hi;
  if (!submap.submap_in_local.IsFinite() || !submap.grid.KnownBounds(&lo, &hi)) return;
  const OccupancyGrid& source = submap.grid;
  // The known box's corners in the local frame bound the target region.
  const double r = source.resolution();
  Eigen::Vector2d box_min = Eigen::Vector2d::Constant(1e300), box_max = -box_min;
  for (int cx : {lo.x(), hi.x() + 1}) {
    for (int cy : {lo.y(), hi.y() + 1}) {
      const Eigen::Vector2d corner_in_submap = source.origin() + r * Eigen::Vector2d(cx, cy);
      const Eigen::Vector2d corner = submap.submap_in_local * corner_in_submap;
      box_min = box_min.cwiseMin(corner);
      box_max = box_max.cwiseMax(corner);
    }
  }
  grid->GrowToInclude(box_min, box_max);
  const Rigid2d local_to_submap = submap.submap_in_local.inverse();
  const CellIndex target_lo = grid->CellAt(box_min), target_hi = grid->CellAt(box_max);
  for (int y = target_lo.y(); y <= target_hi.y(); ++y) {
    for (int x = target_lo.x(); x <= target_hi.x(); ++x) {
      const CellIndex cell(x, y);
      const float value = source.LogOdds(source.CellAt(local_to_submap * grid->CellCenter(cell)));
      if (value != 0.0f) grid->AddLogOdds(cell, value);
    }
  }
}

}  // namespace fleetmap

#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PACKED_SUBMAP_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PACKED_SUBMAP_H_

#include <string>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"
#include "shared/core/submap.h"

namespace fleetmap {

// A submap kept for later at a fraction of its size: the grid's float cells in one zstd frame
// (lossless; most cells are unknown zeros or repeat a few log-odds values). The offline tool
// keeps every submap until it writes the map; unpacked they took 52 MB on the intel lab, about a
// third of the RBPF's peak.
struct PackedSubmap {
  Submap header;  // everything but the grid's cells (its grid is empty)
  OccupancyGridOptions grid_options;
  Eigen::Vector2d grid_origin = Eigen::Vector2d::Zero();
  int grid_width = 0;
  int grid_height = 0;
  std::string compressed_cells;
};

PackedSubmap PackSubmap(Submap submap);
// The submap as it was packed, cell for cell.
Submap UnpackSubmap(const PackedSubmap& packed);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PACKED_SUBMAP_H_

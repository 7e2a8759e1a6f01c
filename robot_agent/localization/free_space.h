#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_FREE_SPACE_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_FREE_SPACE_H_

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// Where a robot may be: the free cells of a known map, or a box when there is no grid (e.g.
// landmark-only localization). Used for uniform initialization, random injection and for
// discounting particles that drift into walls or unknown space.
class FreeSpace {
 public:
  // Cells whose occupancy probability is below `free_probability` are free.
  static FreeSpace FromGrid(const OccupancyGrid& grid, float free_probability = 0.35f);
  static FreeSpace FromBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max);

  bool empty() const { return area_ <= 0.0; }
  // Square metres of free space.
  double area() const { return area_; }
  bool IsFree(const Eigen::Vector2d& point) const;
  // A uniformly distributed free point (the map centre of an empty space).
  Eigen::Vector2d SamplePoint(std::mt19937& rng) const;

 private:
  FreeSpace() = default;

  bool is_box_ = false;
  Eigen::Vector2d min_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_ = Eigen::Vector2d::Zero();
  // Grid mode.
  double resolution_ = 0.0;
  int width_ = 0;
  int height_ = 0;
  std::vector<uint8_t> free_mask_;    // row-major, 1 = free
  std::vector<int32_t> free_cells_;  // indices into free_mask_
  double area_ = 0.0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_FREE_SPACE_H_

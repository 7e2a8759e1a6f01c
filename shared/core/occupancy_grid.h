#ifndef FLEETMAP_SHARED_CORE_OCCUPANCY_GRID_H_
#define FLEETMAP_SHARED_CORE_OCCUPANCY_GRID_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct OccupancyGridOptions {
  double resolution = 0.05;     // metres per cell
  float log_odds_hit = 0.85f;   // added at a beam's end point (p = 0.70)
  float log_odds_miss = -0.4f;  // added along a beam (p = 0.40)
  float log_odds_min = -4.0f;   // clamps keep cells able to change their mind
  float log_odds_max = 4.0f;
  // Beams are traced at most this far (metres); 0 means up to the scan's range_max.
  float max_trace_range = 0.0f;
  // A no-return beam tells us the first metres along it were free; clear this far along it.
  // 0 leaves no-return beams out entirely (the safe choice for glass and sensor dropouts).
  float no_return_free_distance = 0.0f;
};

// Integer cell coordinates: x grows to the right (world +x), y grows up (world +y).
using CellIndex = Eigen::Array2i;

// A log-odds occupancy grid that grows as needed. Cell (0, 0) has its lower-left corner at
// `origin()` in the map frame. A cell whose log-odds is exactly 0 has never been observed.
class OccupancyGrid {
 public:
  explicit OccupancyGrid(const OccupancyGridOptions& options = OccupancyGridOptions());
  // A grid of fixed initial extent (it still grows when updated outside).
  OccupancyGrid(const OccupancyGridOptions& options, const Eigen::Vector2d& origin, int width,
                int height);

  const OccupancyGridOptions& options() const { return options_; }
  double resolution() const { return options_.resolution; }
  const Eigen::Vector2d& origin() const { return origin_; }
  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0 || height_ == 0; }

  CellIndex CellAt(const Eigen::Vector2d& point_in_map) const;
  Eigen::Vector2d CellCenter(const CellIndex& cell) const;
  bool Contains(const CellIndex& cell) const;

  // Reads return 0 (unknown) outside the grid.
  float LogOdds(const CellIndex& cell) const;
  float Probability(const CellIndex& cell) const;
  bool IsKnown(const CellIndex& cell) const { return LogOdds(cell) != 0.0f; }

  // Writes grow the grid when the cell lies outside it.
  void SetLogOdds(const CellIndex& cell, float log_odds);
  void AddLogOdds(const CellIndex& cell, float delta);

  // Ray-traced update: every cell a beam crosses gets `log_odds_miss`, the cell holding its end
  // point gets `log_odds_hit`. No-return beams never mark anything occupied.
  void InsertScan(const LaserScan& scan, const Rigid2d& robot_in_map);

  // Makes sure the axis-aligned box [min, max] (map frame) lies inside the grid.
  void GrowToInclude(const Eigen::Vector2d& min, const Eigen::Vector2d& max);

  // Row-major cells, index = y * width + x.
  const std::vector<float>& log_odds() const { return cells_; }
  // The inclusive box of observed cells; false when no cell has been observed.
  bool KnownBounds(CellIndex* min_cell, CellIndex* max_cell) const;

 private:
  int Index(const CellIndex& cell) const { return cell.y() * width_ + cell.x(); }
  // Grows so that `cell` is inside; returns the (possibly shifted) cell index.
  CellIndex EnsureContains(const CellIndex& cell);
  void Resize(const CellIndex& new_min, const CellIndex& new_max);
  void UpdateCell(int index, float delta);

  OccupancyGridOptions options_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  std::vector<float> cells_;
};

inline float LogOddsToProbability(float log_odds) { return 1.0f / (1.0f + std::exp(-log_odds)); }
float ProbabilityToLogOdds(float probability);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_OCCUPANCY_GRID_H_

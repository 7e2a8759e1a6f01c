#ifndef FLEETMAP_MAP_SERVER_MERGE_LOG_ODDS_CANVAS_H_
#define FLEETMAP_MAP_SERVER_MERGE_LOG_ODDS_CANVAS_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// An axis-aligned box in a map frame (metres).
struct Box2d {
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
};

// Unclamped sums of submap log-odds on a fixed lattice (cell (i, j) covers
// [i, i + 1) x [j, j + 1) times the resolution), growing as needed. Because the sums are not
// clamped, a submap's contribution can be taken out again exactly when it moves: this is what
// makes re-rendering incremental.
class LogOddsCanvas {
 public:
  explicit LogOddsCanvas(double resolution = 0.05) : resolution_(resolution) {}

  double resolution() const { return resolution_; }
  bool empty() const { return width_ == 0 || height_ == 0; }
  const Eigen::Array2i& min_cell() const { return min_cell_; }
  int width() const { return width_; }
  int height() const { return height_; }

  float Sum(int i, int j) const;  // lattice cell; 0 outside
  // Whether some submap observed the cell holding `point` (its sum does not cancel to zero).
  bool ObservedAt(const Eigen::Vector2d& point) const;
  void Add(int i, int j, float value);
  void GrowToInclude(const Eigen::Array2i& lo, const Eigen::Array2i& hi);

  // Adds `weight` times the submap's log-odds (a submap's cell value, aggregated over canvas
  // cells: any wall wins, otherwise the freest sample) placed at `submap_to_frame`.
  void AddSubmap(const OccupancyGrid& submap, const Rigid2d& submap_to_frame, float weight);

  // Adds another canvas of the same resolution (or the part inside `box`), cell by cell.
  void AddCanvas(const LogOddsCanvas& other, const std::optional<Box2d>& box = std::nullopt);

  // The extent of the canvas (empty box when empty).
  Box2d Extent() const;

  // The canvas (or the part inside `box`) as an occupancy grid, sums clamped to the grid's
  // log-odds limits. Cells that cancel to (almost) zero read as unknown.
  OccupancyGrid ToGrid(const OccupancyGridOptions& options,
                       const std::optional<Box2d>& box = std::nullopt) const;

 private:
  double resolution_;
  Eigen::Array2i min_cell_ = Eigen::Array2i::Zero();
  int width_ = 0;
  int height_ = 0;
  std::vector<float> sums_;
};

// The box of a grid's observed cells in its own frame (a pass over the grid).
std::optional<Box2d> KnownBox(const OccupancyGrid& grid);
// The axis-aligned box round `box` once placed at `box_to_frame`.
Box2d PlaceBox(const Box2d& box, const Rigid2d& box_to_frame);
// The bounding box of a submap's observed cells once placed at `submap_to_frame`.
std::optional<Box2d> PlacedBounds(const OccupancyGrid& submap, const Rigid2d& submap_to_frame);
// Grows `region` (empty: none yet) to cover `box` (empty: nothing).
void Include(std::optional<Box2d>* region, const std::optional<Box2d>& box);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_LOG_ODDS_CANVAS_H_

#ifndef FLEETMAP_MAP_SERVER_MERGE_TRAIL_WALLS_H_
#define FLEETMAP_MAP_SERVER_MERGE_TRAIL_WALLS_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// Walls a robot's body explains. Without detections, robots map each other's bodies where they
// pass: blobs of "wall" on the other robot's path, which the other robot's own scans saw free
// once it had moved on. Counted as walls seen through, they made true joins look contradicted
// (docs/BENCHMARKS.md, issue 8, session 24). A real wall is never wholly on a path: robots do
// not drive through walls.

// Where robots drove: the cells (of `resolution`) whose centres lie within `radius` of one of
// `positions`.
class TrailMask {
 public:
  TrailMask(const std::vector<Eigen::Vector2d>& positions, double radius, double resolution);
  bool Contains(const Eigen::Vector2d& point) const;

 private:
  double resolution_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  std::vector<bool> cells_;
};

// The wall cells (log-odds above `occupied_log_odds`) of a grid, grouped into 8-connected blobs.
class WallBlobs {
 public:
  WallBlobs(const OccupancyGrid& grid, float occupied_log_odds);

  // The blob of the wall cell holding `point` (grid frame); -1 when that cell is not a wall.
  int BlobAt(const Eigen::Vector2d& point) const;
  int size() const { return static_cast<int>(blob_cells_.size()); }
  // Per blob: whether every one of its cell centres, moved by `grid_to_trails`, lies on
  // `trails`.
  std::vector<bool> OnTrails(const TrailMask& trails, const Rigid2d& grid_to_trails) const;

 private:
  Eigen::Vector2d origin_;
  double resolution_;
  int width_;
  int height_;
  std::vector<int> label_;  // per grid cell, -1 where not a wall
  std::vector<std::vector<Eigen::Vector2d>> blob_cells_;  // cell centres, grid frame
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_TRAIL_WALLS_H_

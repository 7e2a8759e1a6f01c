#ifndef FLEETMAP_SHARED_EVAL_WALL_SCORE_H_
#define FLEETMAP_SHARED_EVAL_WALL_SCORE_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// The true walls a map is scored against: a grid of wall cells (a simulator world's occupied
// cells, or a true map's). Answers "is this point within `reach` cells of a wall": the
// point's cell, or one of the cells around it up to `reach` away along x and y, is a wall. With
// reach 1 that is the wall cell and its 8 neighbours, the issues' "within 1 cell of a true wall".
class WallMask {
 public:
  // `wall` holds width * height flags, row by row from the cell at `origin` (its lower-left
  // corner). Unknown cells (the simulator's worlds have a band of them round the building) and
  // points outside the grid are not walls: a map cell that lands there is wrong.
  WallMask(const Eigen::Vector2d& origin, double resolution, int width, int height,
           const std::vector<uint8_t>& wall, int reach = 1);
  // A true map read from a file: its occupied cells are the walls.
  static WallMask FromTrueMap(const OccupancyGrid& truth, int reach = 1);

  bool NearWall(const Eigen::Vector2d& point) const;

 private:
  Eigen::Vector2d origin_;
  double resolution_;
  int width_;
  int height_;
  std::vector<uint8_t> near_;  // a wall within `reach` cells
};

// How many of a map's occupied cells lie on true walls. "Occupied" is what the exported map
// shows occupied (probability above the map YAML's occupied_thresh, 0.65), so a map scores the
// same in memory and read back from its file.
struct WallScore {
  int64_t occupied = 0;
  int64_t near_wall = 0;
  double fraction() const { return occupied > 0 ? static_cast<double>(near_wall) / occupied : 0.0; }
};

// The map placed in the truth's frame at `map_in_truth`.
WallScore ScoreOnWalls(const OccupancyGrid& map, const Rigid2d& map_in_truth,
                       const WallMask& walls);

// The same score at the best placement near `initial` (FitMapToWalls): the map's shape alone,
// without the placement of its frame. `best` receives the placement when given.
WallScore ScoreOnWallsBestFit(const OccupancyGrid& map, const Rigid2d& initial,
                              const WallMask& walls, Rigid2d* best = nullptr);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_WALL_SCORE_H_

#include "robot_agent/sim/map_accuracy.h"

namespace fleetmap::sim {

MapAccuracy ScoreAgainstWalls(const OccupancyGrid& grid, const Rigid2d& grid_in_world,
                              const World& world) {
  MapAccuracy accuracy;
  const double r = world.resolution();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (grid.LogOdds(CellIndex(x, y)) <= 0.0f) continue;
      ++accuracy.occupied;
      const Eigen::Vector2d p = grid_in_world * grid.CellCenter(CellIndex(x, y));
      bool hit = false;
      for (int dy = -1; dy <= 1 && !hit; ++dy) {
        for (int dx = -1; dx <= 1 && !hit; ++dx)
          hit = world.IsBlockedAt(p + Eigen::Vector2d(dx * r, dy * r));
      }
      accuracy.near_wall += hit;
    }
  }
  return accuracy;
}

}  // namespace fleetmap::sim

#include "robot_agent/sim/map_accuracy.h"

#include <vector>

#include "shared/eval/map_fit.h"

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

MapAccuracy ScoreAgainstWallsBestFit(const OccupancyGrid& grid, const Rigid2d& initial,
                                     const World& world, Rigid2d* best) {
  // Near-wall world cells (blocked, or a blocked cell among the 8 around): the rule above, read
  // once per point instead of nine times.
  std::vector<uint8_t> near(static_cast<size_t>(world.width()) * world.height(), 0);
  for (int y = 0; y < world.height(); ++y) {
    for (int x = 0; x < world.width(); ++x) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (world.IsBlocked(x + dx, y + dy)) near[static_cast<size_t>(y) * world.width() + x] = 1;
        }
      }
    }
  }
  std::vector<Eigen::Vector2d> occupied;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (grid.LogOdds(CellIndex(x, y)) > 0.0f)
        occupied.push_back(grid.CellCenter(CellIndex(x, y)));
    }
  }
  const MapFit fit = FitMapToWalls(occupied, initial, [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2i c = world.CellAt(p);
    // Outside the world counts as blocked, as in IsBlocked().
    return !world.Contains(c.x(), c.y()) ||
           near[static_cast<size_t>(c.y()) * world.width() + c.x()];
  });
  if (best) *best = fit.placement;
  MapAccuracy accuracy;
  accuracy.occupied = static_cast<int64_t>(occupied.size());
  accuracy.near_wall = fit.on_wall;
  return accuracy;
}

}  // namespace fleetmap::sim

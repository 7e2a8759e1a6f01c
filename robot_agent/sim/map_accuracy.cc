#include "robot_agent/sim/map_accuracy.h"

#include <vector>

namespace fleetmap::sim {

WallMask WorldWalls(const World& world, int reach) {
  std::vector<uint8_t> wall(static_cast<size_t>(world.width()) * world.height(), 0);
  for (int y = 0; y < world.height(); ++y) {
    for (int x = 0; x < world.width(); ++x) {
      wall[static_cast<size_t>(y) * world.width() + x] = world.State(x, y) == CellState::kOccupied;
    }
  }
  return WallMask(world.origin(), world.resolution(), world.width(), world.height(), wall, reach);
}

}  // namespace fleetmap::sim

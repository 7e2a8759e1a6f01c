#include "tests/slam/slam_test_worlds.h"

namespace fleetmap::testing {

SegmentWorld CorridorRing() {
  SegmentWorld world = BoxWorld(Eigen::Vector2d(-10.0, -7.5), Eigen::Vector2d(10.0, 7.5));
  AddBox(Eigen::Vector2d(-8.0, -5.5), Eigen::Vector2d(8.0, 5.5), &world);
  for (double x = -8.0; x <= 8.0; x += 2.7) {
    AddBox(Eigen::Vector2d(x, -7.5), Eigen::Vector2d(x + 0.3, -7.2), &world);
    AddBox(Eigen::Vector2d(x + 1.1, 7.2), Eigen::Vector2d(x + 1.4, 7.5), &world);
  }
  for (double y = -5.0; y <= 5.0; y += 2.3) {
    AddBox(Eigen::Vector2d(-10.0, y), Eigen::Vector2d(-9.7, y + 0.3), &world);
    AddBox(Eigen::Vector2d(9.7, y + 0.8), Eigen::Vector2d(10.0, y + 1.1), &world);
  }
  return world;
}

}  // namespace fleetmap::testing

#ifndef FLEETMAP_TESTS_LOCALIZATION_LOCALIZATION_WORLD_H_
#define FLEETMAP_TESTS_LOCALIZATION_LOCALIZATION_WORLD_H_

// Small synthetic rooms for the localization tests: the segment world (for exact scans) and the
// matching occupancy grid (the known map).

#include <vector>

#include "robot_agent/localization/particle.h"
#include "shared/core/occupancy_grid.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

struct Room {
  SegmentWorld walls;
  Eigen::Vector2d min;  // the outer box
  Eigen::Vector2d max;
  OccupancyGrid grid;
};

// A 6 m x 3 m empty rectangle: every pose has a twin rotated by 180 degrees about the centre.
Room SymmetricRoom();
// An 8 m x 5 m room with an inner box and a wall stub that break every symmetry.
Room AsymmetricRoom();

// The pose that looks exactly like `pose` in SymmetricRoom().
Rigid2d SymmetricTwin(const Room& room, const Rigid2d& pose);

// Total weight of the particles within `radius` metres and `angle` radians of `pose`.
double MassNear(const std::vector<Particle>& particles, const Rigid2d& pose, double radius = 0.5,
                double angle = 0.5);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_LOCALIZATION_LOCALIZATION_WORLD_H_

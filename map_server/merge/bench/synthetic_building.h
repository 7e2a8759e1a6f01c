#ifndef FLEETMAP_MAP_SERVER_MERGE_BENCH_SYNTHETIC_BUILDING_H_
#define FLEETMAP_MAP_SERVER_MERGE_BENCH_SYNTHETIC_BUILDING_H_

// A synthetic multi-robot scenario for the merge benchmark: a building of rooms joined by
// doorways with random clutter, robots touring it from unknown start frames, exact 360-degree
// scans, submaps and detections with known ground truth.

#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"
#include "shared/core/submap.h"

namespace fleetmap::bench {

struct Wall {
  Eigen::Vector2d a;
  Eigen::Vector2d b;
};

struct Building {
  int rooms_x = 4;
  int rooms_y = 3;
  double room_w = 12.0;
  double room_h = 10.0;
  std::vector<Wall> walls;
  Eigen::Vector2d RoomCenter(int i, int j) const {
    return Eigen::Vector2d((i + 0.5) * room_w, (j + 0.5) * room_h);
  }
};

Building MakeBuilding(int rooms_x, int rooms_y, std::mt19937* rng);

// Distance along a ray to the first wall, or +inf.
double CastRay(const Building& b, const Eigen::Vector2d& origin, double angle, double max_range);
LaserScan Scan(const Building& b, const Rigid2d& robot_in_world, double time);
double DistanceToWalls(const Building& b, const Eigen::Vector2d& p);

// A random tour: room centre -> doorway -> neighbouring room centre, one pose per `step` metres.
std::vector<Rigid2d> RandomTour(const Building& b, int steps, double step, std::mt19937* rng);

}  // namespace fleetmap::bench

#endif  // FLEETMAP_MAP_SERVER_MERGE_BENCH_SYNTHETIC_BUILDING_H_

#ifndef FLEETMAP_SHARED_EVAL_MAP_FIT_H_
#define FLEETMAP_SHARED_EVAL_MAP_FIT_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// The placement of a map near `initial` that puts the most of its wall points on true walls
// (`on_wall` says whether a point, in the truth's frame, is on one), and how many it puts there.
// A lattice search within about 0.18 m and 0.35 degrees of `initial`, to 5 mm and 0.01 degrees.
// What it is for: a merged map's frame is free (the robots' starts are unknown); scored where
// one robot's true start places it, the figure also counts how well the merge placed that one
// robot's frame against the rest, not only the map's shape.
struct MapFit {
  Rigid2d placement;
  int64_t on_wall = 0;
};
MapFit FitMapToWalls(const std::vector<Eigen::Vector2d>& wall_points, const Rigid2d& initial,
                     const std::function<bool(const Eigen::Vector2d&)>& on_wall);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_MAP_FIT_H_

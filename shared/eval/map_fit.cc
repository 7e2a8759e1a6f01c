#include "shared/eval/map_fit.h"

#include <cmath>

namespace fleetmap {

MapFit FitMapToWalls(const std::vector<Eigen::Vector2d>& wall_points, const Rigid2d& initial,
                     const std::function<bool(const Eigen::Vector2d&)>& on_wall) {
  const auto count = [&](const Rigid2d& placement) {
    int64_t hits = 0;
    for (const Eigen::Vector2d& p : wall_points) hits += on_wall(placement * p);
    return hits;
  };
  // Two lattices: 2 cm and 0.05 degree steps over +-0.16 m and +-0.3 degrees, then 5 mm and
  // 0.01 degree steps over +-2 cm and +-0.05 degrees around the best.
  struct Lattice {
    double step;
    int steps;
    double angular_step;
    int turns;
  };
  const double degree = M_PI / 180.0;
  MapFit best{initial, count(initial)};
  for (const Lattice& l :
       {Lattice{0.02, 8, 0.05 * degree, 6}, Lattice{0.005, 4, 0.01 * degree, 5}}) {
    const Rigid2d center = best.placement;
    for (int a = -l.turns; a <= l.turns; ++a) {
      for (int iy = -l.steps; iy <= l.steps; ++iy) {
        for (int ix = -l.steps; ix <= l.steps; ++ix) {
          const Rigid2d placement(center.translation() + l.step * Eigen::Vector2d(ix, iy),
                                  center.rotation() + a * l.angular_step);
          const int64_t hits = count(placement);
          if (hits > best.on_wall) best = {placement, hits};
        }
      }
    }
  }
  return best;
}

}  // namespace fleetmap

#include "tests/localization/localization_world.h"

#include <algorithm>
#include <cmath>

namespace fleetmap::testing {
namespace {

double DistanceToSegment(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d ab = s.b - s.a;
  const double t = std::clamp((p - s.a).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
  return (p - (s.a + t * ab)).norm();
}

// Walls become occupied cells; cells inside the outer box and off the walls become free.
OccupancyGrid Rasterize(const SegmentWorld& walls, const Eigen::Vector2d& min,
                        const Eigen::Vector2d& max, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& solid) {
  OccupancyGridOptions options;
  options.resolution = 0.05;
  const Eigen::Vector2d origin = min - Eigen::Vector2d(0.5, 0.5);
  const int width = static_cast<int>(std::ceil((max.x() - min.x() + 1.0) / options.resolution));
  const int height = static_cast<int>(std::ceil((max.y() - min.y() + 1.0) / options.resolution));
  OccupancyGrid grid(options, origin, width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const CellIndex cell(x, y);
      const Eigen::Vector2d c = grid.CellCenter(cell);
      double d = 1e9;
      for (const Segment& s : walls) d = std::min(d, DistanceToSegment(c, s));
      bool inside_solid = false;
      for (const auto& box : solid) {
        inside_solid |= (c.array() > box.first.array()).all() && (c.array() < box.second.array()).all();
      }
      if (d < 0.04) {
        grid.SetLogOdds(cell, options.log_odds_max);
      } else if (!inside_solid && (c.array() > min.array()).all() && (c.array() < max.array()).all()) {
        grid.SetLogOdds(cell, options.log_odds_min);
      }
    }
  }
  return grid;
}

}  // namespace

Room SymmetricRoom() {
  Room room{BoxWorld({0, 0}, {6, 3}), {0, 0}, {6, 3}, OccupancyGrid()};
  room.grid = Rasterize(room.walls, room.min, room.max, {});
  return room;
}

Room AsymmetricRoom() {
  Room room{BoxWorld({0, 0}, {8, 5}), {0, 0}, {8, 5}, OccupancyGrid()};
  AddBox({5.5, 3.0}, {6.5, 4.0}, &room.walls);
  room.walls.push_back({{3.0, 0.0}, {3.0, 1.5}});
  room.grid = Rasterize(room.walls, room.min, room.max, {{{5.5, 3.0}, {6.5, 4.0}}});
  return room;
}

Rigid2d SymmetricTwin(const Room& room, const Rigid2d& pose) {
  return Rigid2d(room.min + room.max - pose.translation(), pose.rotation() + M_PI);
}

double MassNear(const std::vector<Particle>& particles, const Rigid2d& pose, double radius,
                double angle) {
  double mass = 0.0, total = 0.0;
  for (const Particle& p : particles) {
    total += p.weight;
    if ((p.robot_in_map.translation() - pose.translation()).norm() <= radius &&
        std::abs(NormalizeAngle(p.robot_in_map.rotation() - pose.rotation())) <= angle) {
      mass += p.weight;
    }
  }
  return total > 0.0 ? mass / total : 0.0;
}

}  // namespace fleetmap::testing

#include "map_server/merge/bench/synthetic_building.h"

#include <cmath>
#include <limits>

namespace fleetmap::bench {
namespace {

void Add(std::vector<Wall>* walls, double ax, double ay, double bx, double by) {
  walls->push_back({Eigen::Vector2d(ax, ay), Eigen::Vector2d(bx, by)});
}

void AddBox(std::vector<Wall>* walls, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  Add(walls, lo.x(), lo.y(), hi.x(), lo.y());
  Add(walls, hi.x(), lo.y(), hi.x(), hi.y());
  Add(walls, hi.x(), hi.y(), lo.x(), hi.y());
  Add(walls, lo.x(), hi.y(), lo.x(), lo.y());
}

double PointSegment(const Eigen::Vector2d& p, const Wall& w) {
  const Eigen::Vector2d d = w.b - w.a;
  const double t = std::clamp((p - w.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (w.a + t * d - p).norm();
}

}  // namespace

Building MakeBuilding(int rooms_x, int rooms_y, std::mt19937* rng) {
  Building b;
  b.rooms_x = rooms_x;
  b.rooms_y = rooms_y;
  const double door = 1.6;
  const double w = b.room_w, h = b.room_h;
  AddBox(&b.walls, Eigen::Vector2d(0, 0), Eigen::Vector2d(rooms_x * w, rooms_y * h));
  // Internal walls with a doorway in the middle of every room side.
  for (int i = 1; i < rooms_x; ++i) {
    for (int j = 0; j < rooms_y; ++j) {
      const double x = i * w, yc = (j + 0.5) * h;
      Add(&b.walls, x, j * h, x, yc - door / 2);
      Add(&b.walls, x, yc + door / 2, x, (j + 1) * h);
    }
  }
  for (int j = 1; j < rooms_y; ++j) {
    for (int i = 0; i < rooms_x; ++i) {
      const double y = j * h, xc = (i + 0.5) * w;
      Add(&b.walls, i * w, y, xc - door / 2, y);
      Add(&b.walls, xc + door / 2, y, (i + 1) * w, y);
    }
  }
  // Clutter in each quadrant of each room, away from the tour lines through the centre.
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < rooms_x; ++i) {
    for (int j = 0; j < rooms_y; ++j) {
      const Eigen::Vector2d c = b.RoomCenter(i, j);
      for (int q = 0; q < 4; ++q) {
        if (u(*rng) < 0.3) continue;
        const double sx = (q & 1) ? 1.0 : -1.0, sy = (q & 2) ? 1.0 : -1.0;
        const double size_x = 0.4 + 1.6 * u(*rng), size_y = 0.3 + 1.2 * u(*rng);
        const double off_x = 1.5 + (w / 2 - 2.2 - size_x) * u(*rng);
        const double off_y = 1.5 + (h / 2 - 2.2 - size_y) * u(*rng);
        const Eigen::Vector2d lo(c.x() + sx * off_x - (sx < 0 ? size_x : 0), c.y() + sy * off_y - (sy < 0 ? size_y : 0));
        if (u(*rng) < 0.3) {
          Add(&b.walls, lo.x(), lo.y(), lo.x() + size_x, lo.y() + size_y);  // a slanted panel
        } else {
          AddBox(&b.walls, lo, lo + Eigen::Vector2d(size_x, size_y));
        }
      }
    }
  }
  return b;
}

double CastRay(const Building& b, const Eigen::Vector2d& origin, double angle, double max_range) {
  const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& s : b.walls) {
    const Eigen::Vector2d e = s.b - s.a;
    const double denom = dir.x() * e.y() - dir.y() * e.x();
    if (std::abs(denom) < 1e-12) continue;
    const Eigen::Vector2d q = s.a - origin;
    const double t = (q.x() * e.y() - q.y() * e.x()) / denom;
    const double v = (q.x() * dir.y() - q.y() * dir.x()) / denom;
    if (t >= 0.0 && v >= 0.0 && v <= 1.0) best = std::min(best, t);
  }
  return best <= max_range ? best : std::numeric_limits<double>::infinity();
}

LaserScan Scan(const Building& b, const Rigid2d& robot_in_world, double time) {
  std::vector<float> ranges;
  for (int i = 0; i < 360; ++i) {
    const double a = -M_PI + i * M_PI / 180.0;
    ranges.push_back(static_cast<float>(CastRay(b, robot_in_world.translation(), robot_in_world.rotation() + a, 8.0)));
  }
  return MakeLaserScan(time, static_cast<float>(-M_PI), static_cast<float>(M_PI / 180), 0.0f, 8.0f, ranges);
}

double DistanceToWalls(const Building& b, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& w : b.walls) best = std::min(best, PointSegment(p, w));
  return best;
}

std::vector<Rigid2d> RandomTour(const Building& b, int steps, double step, std::mt19937* rng) {
  std::uniform_int_distribution<int> rx(0, b.rooms_x - 1), ry(0, b.rooms_y - 1), dir(0, 3);
  int i = rx(*rng), j = ry(*rng);
  std::vector<Rigid2d> path;
  Eigen::Vector2d at = b.RoomCenter(i, j);
  while (static_cast<int>(path.size()) < steps) {
    int ni = i, nj = j;
    do {
      const int d = dir(*rng);
      ni = i + (d == 0) - (d == 1);
      nj = j + (d == 2) - (d == 3);
    } while (ni < 0 || nj < 0 || ni >= b.rooms_x || nj >= b.rooms_y);
    const Eigen::Vector2d target = b.RoomCenter(ni, nj);
    const Eigen::Vector2d d = target - at;
    const double heading = std::atan2(d.y(), d.x());
    const int n = static_cast<int>(std::ceil(d.norm() / step));
    for (int k = 0; k < n && static_cast<int>(path.size()) < steps; ++k) {
      // A gentle weave so consecutive poses are not all collinear.
      const Eigen::Vector2d p = at + d * (static_cast<double>(k) / n);
      path.emplace_back(p, heading + 0.2 * std::sin(0.3 * static_cast<double>(path.size())));
    }
    at = target;
    i = ni;
    j = nj;
  }
  return path;
}

}  // namespace fleetmap::bench

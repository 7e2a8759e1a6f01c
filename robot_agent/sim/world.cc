#include "robot_agent/sim/world.h"

#include <cmath>
#include <limits>

namespace fleetmap::sim {

World::World(double resolution, const Eigen::Vector2d& origin, int width, int height)
    : resolution_(resolution),
      origin_(origin),
      width_(width),
      height_(height),
      cells_(static_cast<size_t>(width) * static_cast<size_t>(height),
             static_cast<uint8_t>(CellState::kFree)) {}

Eigen::Vector2i World::CellAt(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d local = (point - origin_) / resolution_;
  return Eigen::Vector2i(static_cast<int>(std::floor(local.x())),
                         static_cast<int>(std::floor(local.y())));
}

Eigen::Vector2d World::CellCenter(int x, int y) const {
  return origin_ + resolution_ * Eigen::Vector2d(x + 0.5, y + 0.5);
}

bool World::IsBlockedAt(const Eigen::Vector2d& point) const {
  const Eigen::Vector2i cell = CellAt(point);
  return IsBlocked(cell.x(), cell.y());
}

RayHit World::CastRay(const Eigen::Vector2d& from, double angle, double max_range) const {
  RayHit result;
  const double dx = std::cos(angle);
  const double dy = std::sin(angle);
  Eigen::Vector2i cell = CellAt(from);
  if (IsBlocked(cell.x(), cell.y())) {
    result.hit = true;
    result.point = from;
    return result;
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int step_x = dx > 0 ? 1 : -1;
  const int step_y = dy > 0 ? 1 : -1;
  const Eigen::Vector2d local = (from - origin_) / resolution_;
  // Distance along the ray (metres) to the next x / y cell boundary, and between boundaries.
  const double next_x = step_x > 0 ? cell.x() + 1.0 : cell.x();
  const double next_y = step_y > 0 ? cell.y() + 1.0 : cell.y();
  double t_max_x = dx != 0.0 ? (next_x - local.x()) * resolution_ / dx : kInf;
  double t_max_y = dy != 0.0 ? (next_y - local.y()) * resolution_ / dy : kInf;
  const double t_delta_x = dx != 0.0 ? resolution_ / std::abs(dx) : kInf;
  const double t_delta_y = dy != 0.0 ? resolution_ / std::abs(dy) : kInf;
  while (true) {
    double t;
    bool x_face;
    if (t_max_x < t_max_y) {
      t = t_max_x;
      t_max_x += t_delta_x;
      cell.x() += step_x;
      x_face = true;
    } else {
      t = t_max_y;
      t_max_y += t_delta_y;
      cell.y() += step_y;
      x_face = false;
    }
    if (t > max_range) break;
    if (IsBlocked(cell.x(), cell.y())) {
      result.hit = true;
      result.distance = t;
      result.point = from + t * Eigen::Vector2d(dx, dy);
      result.x_face = x_face;
      return result;
    }
  }
  result.distance = max_range;
  result.point = from + max_range * Eigen::Vector2d(dx, dy);
  return result;
}

bool World::LineOfSight(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  const Eigen::Vector2d delta = b - a;
  const double length = delta.norm();
  if (length < 1e-12) return !IsBlockedAt(a);
  return !CastRay(a, std::atan2(delta.y(), delta.x()), length).hit;
}

const WallPatch* World::PatchAt(const Eigen::Vector2d& point) const {
  const WallPatch* found = nullptr;
  for (const WallPatch& patch : patches) {
    if (point.x() >= patch.min.x() && point.x() <= patch.max.x() && point.y() >= patch.min.y() &&
        point.y() <= patch.max.y()) {
      found = &patch;
    }
  }
  return found;
}

std::optional<Place> World::FindPlace(const std::string& place_name) const {
  for (const Place& place : places) {
    if (place.name == place_name) return place;
  }
  return std::nullopt;
}

}  // namespace fleetmap::sim

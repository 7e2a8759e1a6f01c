#include "robot_agent/sim/path_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace fleetmap::sim {

double PathLength(const Path& path) {
  double length = 0.0;
  for (size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

bool IsDiskFree(const World& world, const Eigen::Vector2d& center, double radius) {
  const Eigen::Vector2i lo = world.CellAt(center - Eigen::Vector2d(radius, radius));
  const Eigen::Vector2i hi = world.CellAt(center + Eigen::Vector2d(radius, radius));
  const double res = world.resolution();
  for (int y = lo.y(); y <= hi.y(); ++y) {
    for (int x = lo.x(); x <= hi.x(); ++x) {
      if (!world.IsBlocked(x, y)) continue;
      // Closest point of the cell to the centre.
      const Eigen::Vector2d cell_min = world.origin() + res * Eigen::Vector2d(x, y);
      const Eigen::Vector2d closest =
          center.cwiseMax(cell_min).cwiseMin(cell_min + Eigen::Vector2d(res, res));
      if ((closest - center).norm() < radius) return false;
    }
  }
  return true;
}

namespace {

// Planning cells are a whole number of world cells.
int CoarseFactor(const World& world, const PathPlannerOptions& options) {
  return std::max(1, static_cast<int>(std::lround(options.resolution / world.resolution())));
}

PathPlannerOptions Snapped(const World& world, PathPlannerOptions options) {
  options.resolution = CoarseFactor(world, options) * world.resolution();
  return options;
}

}  // namespace

PathPlanner::PathPlanner(const World& world, const PathPlannerOptions& options)
    : options_(Snapped(world, options)), origin_(world.origin()) {
  const int factor = CoarseFactor(world, options);
  const double res = options_.resolution;
  width_ = (world.width() + factor - 1) / factor;
  height_ = (world.height() + factor - 1) / factor;
  constexpr float kFar = 1e9f;
  distance_.assign(static_cast<size_t>(width_) * height_, kFar);
  for (int y = 0; y < world.height(); ++y) {
    for (int x = 0; x < world.width(); ++x) {
      if (world.IsBlocked(x, y)) distance_[Index(x / factor, y / factor)] = 0.0f;
    }
  }
  // Two-pass chamfer distance transform (1, sqrt 2); the grid border counts as blocked.
  const float straight = static_cast<float>(res);
  const float diagonal = static_cast<float>(res * std::sqrt(2.0));
  auto relax = [&](int x, int y, int nx, int ny, float step) {
    const float neighbour = Inside(nx, ny) ? distance_[Index(nx, ny)] : 0.0f;
    float& d = distance_[Index(x, y)];
    d = std::min(d, neighbour + step);
  };
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      relax(x, y, x - 1, y, straight);
      relax(x, y, x, y - 1, straight);
      relax(x, y, x - 1, y - 1, diagonal);
      relax(x, y, x + 1, y - 1, diagonal);
    }
  }
  for (int y = height_ - 1; y >= 0; --y) {
    for (int x = width_ - 1; x >= 0; --x) {
      relax(x, y, x + 1, y, straight);
      relax(x, y, x, y + 1, straight);
      relax(x, y, x + 1, y + 1, diagonal);
      relax(x, y, x - 1, y + 1, diagonal);
    }
  }
}

Eigen::Vector2i PathPlanner::CellAt(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d local = (point - origin_) / options_.resolution;
  return Eigen::Vector2i(static_cast<int>(std::floor(local.x())),
                         static_cast<int>(std::floor(local.y())));
}

Eigen::Vector2d PathPlanner::Center(int x, int y) const {
  return origin_ + options_.resolution * Eigen::Vector2d(x + 0.5, y + 0.5);
}

double PathPlanner::DistanceToWall(const Eigen::Vector2d& point) const {
  const Eigen::Vector2i cell = CellAt(point);
  return Inside(cell.x(), cell.y()) ? distance_[Index(cell.x(), cell.y())] : 0.0;
}

std::optional<Path> PathPlanner::Plan(const Eigen::Vector2d& start,
                                      const Eigen::Vector2d& goal) const {
  const Eigen::Vector2i s = CellAt(start);
  const Eigen::Vector2i g = CellAt(goal);
  if (!Inside(s.x(), s.y()) || !Inside(g.x(), g.y())) return std::nullopt;
  const int start_index = Index(s.x(), s.y());
  const int goal_index = Index(g.x(), g.y());
  // Start and goal may sit a little closer to a wall than the clearance (a robot parked near a
  // wall); everything in between must respect it.
  const float min_endpoint = static_cast<float>(0.5 * options_.clearance);
  if (distance_[start_index] < min_endpoint || distance_[goal_index] < min_endpoint) {
    return std::nullopt;
  }
  const double res = options_.resolution;
  auto heuristic = [&](int index) {
    const double dx = std::abs(index % width_ - g.x());
    const double dy = std::abs(index / width_ - g.y());
    return res * (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));
  };
  auto step_cost = [&](int index, double length) {
    const double d = distance_[index];
    const double shortfall = std::max(0.0, options_.preferred_clearance - d) /
                             options_.preferred_clearance;
    return length * (1.0 + options_.wall_cost * shortfall);
  };
  std::vector<double> cost(distance_.size(), std::numeric_limits<double>::infinity());
  std::vector<int> parent(distance_.size(), -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  cost[start_index] = 0.0;
  open.push({heuristic(start_index), start_index});
  static constexpr int kDx[] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[] = {0, 0, 1, -1, 1, -1, 1, -1};
  bool found = false;
  while (!open.empty()) {
    const auto [priority, index] = open.top();
    open.pop();
    if (index == goal_index) {
      found = true;
      break;
    }
    if (priority - heuristic(index) > cost[index] + 1e-9) continue;  // stale entry
    const int x = index % width_;
    const int y = index / width_;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (!Inside(nx, ny)) continue;
      const int next = Index(nx, ny);
      if (distance_[next] < options_.clearance && next != goal_index) continue;
      const double length = k < 4 ? res : res * std::sqrt(2.0);
      const double candidate = cost[index] + step_cost(next, length);
      if (candidate < cost[next]) {
        cost[next] = candidate;
        parent[next] = index;
        open.push({candidate + heuristic(next), next});
      }
    }
  }
  if (!found) return std::nullopt;
  Path reversed{goal};
  for (int index = parent[goal_index]; index != -1 && index != start_index;
       index = parent[index]) {
    reversed.push_back(Center(index % width_, index / width_));
  }
  reversed.push_back(start);
  return Path(reversed.rbegin(), reversed.rend());
}

}  // namespace fleetmap::sim

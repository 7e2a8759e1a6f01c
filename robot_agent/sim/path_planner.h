#ifndef FLEETMAP_ROBOT_AGENT_SIM_PATH_PLANNER_H_
#define FLEETMAP_ROBOT_AGENT_SIM_PATH_PLANNER_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/sim/world.h"

namespace fleetmap::sim {

struct PathPlannerOptions {
  double resolution = 0.1;   // planning cell size (coarser than the world is fine)
  double clearance = 0.25;   // cells closer than this to a wall are not traversable
  // Steps closer than this to a wall cost more, so paths keep to the middle of corridors.
  double preferred_clearance = 0.8;
  double wall_cost = 4.0;
};

using Path = std::vector<Eigen::Vector2d>;

double PathLength(const Path& path);

// A* over an 8-connected planning grid with a wall-distance cost, built once per world.
class PathPlanner {
 public:
  PathPlanner(const World& world, const PathPlannerOptions& options);

  // Distance (metres, to planning-cell accuracy) from the point to the nearest blocked cell.
  double DistanceToWall(const Eigen::Vector2d& point) const;
  // A path from start to goal (both included), or nothing when the goal cannot be reached.
  std::optional<Path> Plan(const Eigen::Vector2d& start, const Eigen::Vector2d& goal) const;

  const PathPlannerOptions& options() const { return options_; }

 private:
  bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  int Index(int x, int y) const { return y * width_ + x; }
  Eigen::Vector2i CellAt(const Eigen::Vector2d& point) const;
  Eigen::Vector2d Center(int x, int y) const;

  const PathPlannerOptions options_;
  Eigen::Vector2d origin_;
  int width_ = 0;
  int height_ = 0;
  std::vector<float> distance_;  // metres to the nearest blocked planning cell
};

// True when every world cell touching the disk is free (the robot fits there).
bool IsDiskFree(const World& world, const Eigen::Vector2d& center, double radius);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_PATH_PLANNER_H_

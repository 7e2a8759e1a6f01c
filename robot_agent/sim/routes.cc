#include "robot_agent/sim/routes.h"

#include <sstream>

namespace fleetmap::sim {
namespace {

std::string PointString(const Eigen::Vector2d& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ")";
  return os.str();
}

}  // namespace

PathPlannerOptions PlannerOptionsFor(const Scenario& scenario) {
  PathPlannerOptions options;
  options.clearance = scenario.body.radius + 0.05;
  return options;
}

bool PlanRoutes(const Scenario& scenario, const World& world, const PathPlanner& planner,
                std::vector<PlannedRoute>* routes, std::string* error) {
  routes->clear();
  const double radius = scenario.body.radius;
  std::string known_places;
  for (const Place& place : world.places) {
    known_places += (known_places.empty() ? "" : ", ") + place.name;
  }
  if (known_places.empty()) known_places = "none: use [x, y] waypoints";
  for (const RobotSpec& robot : scenario.robots) {
    PlannedRoute route;
    route.start = robot.start;
    if (!robot.start_place.empty()) {
      const std::optional<Place> place = world.FindPlace(robot.start_place);
      if (!place) {
        *error = robot.name + ": unknown start place '" + robot.start_place + "' in world '" +
                 world.name + "' (places: " + known_places + ")";
        return false;
      }
      route.start = Rigid2d(place->position, place->heading);
    }
    if (!IsDiskFree(world, route.start.translation(), radius)) {
      *error = robot.name + ": start " + PointString(route.start.translation()) +
               " is inside a wall (or closer to one than the robot radius " +
               std::to_string(radius) + " m)";
      return false;
    }
    for (size_t other = 0; other < routes->size(); ++other) {
      if (((*routes)[other].start.translation() - route.start.translation()).norm() <
          2 * radius) {
        *error = robot.name + ": start overlaps robot " + scenario.robots[other].name;
        return false;
      }
    }
    route.path.push_back(route.start.translation());
    Eigen::Vector2d from = route.start.translation();
    for (int lap = 0; lap < robot.laps; ++lap) {
      for (size_t i = 0; i < robot.waypoints.size(); ++i) {
        const Waypoint& waypoint = robot.waypoints[i];
        Eigen::Vector2d goal = waypoint.position;
        const std::string label =
            robot.name + ": waypoint " + std::to_string(i + 1) + " " + waypoint.Describe();
        if (!waypoint.place.empty()) {
          const std::optional<Place> place = world.FindPlace(waypoint.place);
          if (!place) {
            *error = label + " is not a place of world '" + world.name + "' (places: " +
                     known_places + ")";
            return false;
          }
          goal = place->position;
        }
        if (!IsDiskFree(world, goal, radius)) {
          *error = label + " at " + PointString(goal) + " is inside a wall or too close to one";
          return false;
        }
        if ((goal - from).norm() < 1e-6) continue;
        const std::optional<Path> segment = planner.Plan(from, goal);
        if (!segment) {
          *error = label + " at " + PointString(goal) + " is unreachable from " +
                   PointString(from) + " (no path with " +
                   std::to_string(planner.options().clearance) + " m clearance)";
          return false;
        }
        route.path.insert(route.path.end(), segment->begin() + 1, segment->end());
        from = goal;
      }
    }
    routes->push_back(std::move(route));
  }
  return true;
}

}  // namespace fleetmap::sim

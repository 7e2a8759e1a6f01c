#ifndef FLEETMAP_ROBOT_AGENT_SIM_ROUTES_H_
#define FLEETMAP_ROBOT_AGENT_SIM_ROUTES_H_

#include <string>
#include <vector>

#include "robot_agent/sim/path_planner.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::sim {

struct PlannedRoute {
  Rigid2d start;  // ground-truth start pose in the world
  Path path;      // start -> every waypoint, `laps` times
};

// Checks everything that needs the world and plans each robot's route: place names exist,
// start poses are free of walls and of each other, every waypoint is reachable. Messages name the
// robot and the waypoint, e.g. "robot2: waypoint 3 'Lab_9' ... is unreachable".
bool PlanRoutes(const Scenario& scenario, const World& world, const PathPlanner& planner,
                std::vector<PlannedRoute>* routes, std::string* error);

// The planner settings used for a scenario (clearance from the robot radius).
PathPlannerOptions PlannerOptionsFor(const Scenario& scenario);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_ROUTES_H_

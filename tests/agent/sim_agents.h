#ifndef FLEETMAP_TESTS_AGENT_SIM_AGENTS_H_
#define FLEETMAP_TESTS_AGENT_SIM_AGENTS_H_

// Agents on a live simulated scenario, for the tests that run several of them against a server.

#include <map>
#include <string>
#include <vector>

#include "robot_agent/agent/agent_config.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::testing {

// Writes `<dir>/corridor_pass.yaml` and returns its path. The rectangle world's south corridor
// spans y in [0.15, 2.2]. robot1 drives east along y = 1.7; robot2 stands at (6.5, 0.6) facing
// west (its route starts after the run ends), so they see each other from 5.3 m down to ~1.9 m
// (the 60 degree field of view), during the 12 s run.
std::string WriteScenario(const std::string& dir);

// True poses of every robot at every tick (ms), from a copy of the deterministic simulation.
std::map<long, std::vector<Rigid2d>> SimGroundTruth(const std::string& scenario);

// Simulated robot `robot` of `scenario` with its camera and detection, as fast as possible, quick
// retries, no map subscription, no status lines; the outbox in `dir`.
AgentConfig SimAgentConfig(const std::string& scenario, const std::string& robot,
                           const std::string& dir, int port);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_AGENT_SIM_AGENTS_H_

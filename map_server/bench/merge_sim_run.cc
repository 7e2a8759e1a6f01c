// fleetmap-merge-sim-bench's run: simulator -> local SLAM -> MergeEngine, scored against the truth.

#include "map_server/bench/merge_sim_run.h"

#include <memory>
#include <utility>

#include "map_server/bench/sim_run.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/simulation.h"
#include "robot_agent/sim/world_io.h"

namespace fleetmap {
namespace {

std::unique_ptr<sim::Simulation> LoadSimulation(const std::string& path, uint64_t seed_offset,
                                                std::string* error) {
  sim::Scenario scenario;
  if (!sim::LoadScenario(path, &scenario, error)) return nullptr;
  scenario.camera.enabled = false;
  scenario.seed += seed_offset;
  sim::World world;
  if (!sim::LoadWorld(scenario.world_path, &world, error)) return nullptr;
  return sim::Simulation::Create(scenario, std::move(world), error);
}

}  // namespace

bool Run(const std::string& scenario, const BenchOptions& options, RunResult* result,
         std::string* error) {
  std::unique_ptr<sim::Simulation> sim = LoadSimulation(scenario, options.seed_offset, error);
  if (!sim) return false;  // the error names the file
  SimRun run(std::move(sim), options, result);
  if (!run.Start(error)) return false;
  run.Drive();
  run.ReportLocalSlam();
  return run.Score(error);
}

}  // namespace fleetmap

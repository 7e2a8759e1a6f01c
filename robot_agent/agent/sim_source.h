#ifndef FLEETMAP_ROBOT_AGENT_AGENT_SIM_SOURCE_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_SIM_SOURCE_H_

#include <deque>
#include <memory>
#include <string>

#include "robot_agent/agent/sensor_source.h"
#include "robot_agent/sim/simulation.h"

namespace fleetmap {

// One robot of a simulated scenario, live: the simulation is stepped as events are asked for.
// Every agent of a scenario runs its own copy of the (deterministic) simulation and keeps only
// its robot's sensors.
class SimSource : public SensorSource {
 public:
  // `scenario`: a scenario file or the name of a shipped one (e.g. "department_3robots").
  static std::unique_ptr<SimSource> Open(const std::string& scenario, const std::string& robot,
                                         bool camera, std::string* error);

  bool Next(SensorEvent* event) override;
  const std::string& error() const override { return error_; }
  std::string Describe() const override;
  // The scenario being run (the detector takes its camera, markers and world from it).
  const sim::Simulation& simulation() const { return *simulation_; }

 private:
  SimSource(std::unique_ptr<sim::Simulation> simulation, int robot_index)
      : simulation_(std::move(simulation)), robot_index_(robot_index) {}

  std::unique_ptr<sim::Simulation> simulation_;
  const int robot_index_;
  std::deque<SensorEvent> ready_;
  std::string error_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_SIM_SOURCE_H_

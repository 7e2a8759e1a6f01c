#include "robot_agent/bench/sim_slam_run.h"

#include <chrono>
#include <memory>
#include <utility>

#include "robot_agent/sim/simulation.h"

namespace fleetmap {

bool RunSimulatedScenario(const std::string& scenario_path, LocalSlam* slam, SimSlamRun* run,
                          std::string* error, OccupancyGrid* truth_map) {
  std::unique_ptr<sim::Simulation> simulation =
      sim::Simulation::FromFile(scenario_path, error, /*camera_enabled=*/false);
  if (!simulation) return false;
  *run = SimSlamRun();
  using Clock = std::chrono::steady_clock;
  Clock::duration spent{};
  auto take_submaps = [&] {
    for (Submap& submap : slam->TakeSubmapUpdates()) run->submaps[submap.submap_id] = std::move(submap);
  };
  while (!simulation->Done()) {
    const sim::StepResult step = simulation->Step();
    for (const sim::SensorPacket& packet : step.packets) {
      if (packet.robot_index != 0) continue;
      const Clock::time_point start = Clock::now();
      if (packet.laser) {
        // As fleetmap-slam and the agent do: odometry from the laser's records, at each scan's
        // instant (the simulator's odometry records run at their own rate, every 0.06 s).
        if (!slam->AddOdometry({packet.laser->scan.timestamp, packet.laser->robot_pose}, error)) {
          return false;
        }
        if (!slam->AddScan(packet.laser->scan, error)) return false;
        run->ground_truth.push_back({packet.laser->scan.timestamp, packet.ground_truth});
        if (++run->scans % 100 == 0) take_submaps();
      }
      spent += Clock::now() - start;
      // Outside the timed part: the backend's time is what the table reports.
      if (packet.laser) run->returns.push_back(ToPointsInRobotFrame(packet.laser->scan));
      if (truth_map && packet.laser) truth_map->InsertScan(packet.laser->scan, packet.ground_truth);
    }
  }
  const Clock::time_point start = Clock::now();
  slam->Finish();
  take_submaps();
  run->estimate = slam->trajectory();
  spent += Clock::now() - start;
  run->slam_seconds = std::chrono::duration<double>(spent).count();
  return true;
}

}  // namespace fleetmap

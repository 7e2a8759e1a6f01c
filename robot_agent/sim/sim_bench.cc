// fleetmap-sim-bench: simulated seconds per wall second of a scenario (library API, cameras
// rendered; optionally with every output file written), and a full-run check of the building lap.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "robot_agent/sim/output_writer.h"
#include "robot_agent/sim/simulation.h"

namespace {

using fleetmap::sim::Simulation;

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Benchmark the simulator."};
  std::string scenario = fleetmap::sim::ShippedScenariosDir() + "/department_3robots.yaml";
  std::string write_dir;
  bool no_camera = false;
  bool building_lap = false;
  app.add_option("--scenario", scenario, "Scenario to time")->capture_default_str();
  app.add_option("--write", write_dir, "Also write all outputs (PNG frames per save policy) here");
  app.add_flag("--no-camera", no_camera, "Do not render camera frames");
  app.add_flag("--building-lap", building_lap,
               "Instead: drive building_1lap fully (no camera) and report the true path length");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  if (building_lap) {
    std::unique_ptr<Simulation> sim = Simulation::FromFile(
        fleetmap::sim::ShippedScenariosDir() + "/building_1lap.yaml", &error, false);
    if (!sim) {
      std::cerr << "fleetmap-sim-bench: " << error << "\n";
      return 1;
    }
    const auto start = std::chrono::steady_clock::now();
    double length = 0.0;
    Eigen::Vector2d last = sim->TruePoses()[0].translation();
    while (!sim->Done()) {
      sim->Step();
      const Eigen::Vector2d now = sim->TruePoses()[0].translation();
      length += (now - last).norm();
      last = now;
    }
    std::printf("building_1lap: ground-truth path %.1f m (planned %.1f m) in %.1f s simulated, "
                "%.1f s wall; lap %s 400 m\n", length,
                fleetmap::sim::PathLength(sim->robots()[0].route.path), sim->time(),
                Seconds(start), length > 400.0 ? ">" : "<=");
    return length > 400.0 ? 0 : 2;
  }

  std::unique_ptr<Simulation> sim = Simulation::FromFile(scenario, &error, !no_camera);
  if (!sim) {
    std::cerr << "fleetmap-sim-bench: " << error << "\n";
    return 1;
  }
  std::unique_ptr<fleetmap::sim::OutputWriter> writer;
  if (!write_dir.empty()) {
    writer = fleetmap::sim::OutputWriter::Open(write_dir, *sim, &error);
    if (!writer) {
      std::cerr << "fleetmap-sim-bench: " << error << "\n";
      return 1;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  long frames = 0;
  while (!sim->Done()) {
    fleetmap::sim::StepResult step = sim->Step();
    for (const auto& packet : step.packets) frames += packet.camera.has_value();
    if (writer && !writer->Write(step, &error)) {
      std::cerr << "fleetmap-sim-bench: " << error << "\n";
      return 1;
    }
  }
  if (writer && !writer->Close(&error)) {
    std::cerr << "fleetmap-sim-bench: " << error << "\n";
    return 1;
  }
  const double wall = Seconds(start);
  const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const double simulated = sim->time() - sim->scenario().start_time;
  std::printf("%s: %zu robots, %.1f s simulated, %ld camera frames rendered%s\n",
              sim->scenario().name.c_str(), sim->robots().size(), simulated, frames,
              writer ? ", outputs written" : " (not written)");
  std::printf("wall %.2f s -> %.1f simulated s per wall s; CPU %.2f s -> %.1f simulated s per "
              "CPU s\n", wall, simulated / wall, cpu, simulated / cpu);
  return 0;
}

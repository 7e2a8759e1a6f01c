// fleetmap-sim: runs a simulator scenario and writes logs, camera frames and ground truth.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "robot_agent/sim/output_writer.h"
#include "robot_agent/sim/simulation.h"

int main(int argc, char** argv) {
  CLI::App app{"Simulate robots driving a scenario; write CARMEN logs, camera frames, ground truth "
               "and a visibility list (see robot_agent/sim/README.md)."};
  std::string scenario_path;
  std::string out_dir;
  bool no_camera = false;
  bool quiet = false;
  bool all_frames = false;
  double duration = 0.0;
  app.add_option("--scenario", scenario_path, "Scenario YAML file")->required();
  app.add_option("--out", out_dir, "Output folder (created)")->required();
  app.add_flag("--no-camera", no_camera, "Do not render camera frames (much faster)");
  app.add_option("--duration", duration, "Stop after this many simulated seconds")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--all-frames", all_frames,
               "Write every rendered frame (default: camera.save_every plus frames with a robot "
               "in view)");
  app.add_flag("--quiet", quiet, "No progress line");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  std::unique_ptr<fleetmap::sim::Simulation> sim =
      fleetmap::sim::Simulation::FromFile(scenario_path, &error, !no_camera);
  if (!sim) {
    std::cerr << "fleetmap-sim: " << error << "\n";
    return 1;
  }
  if (duration > 0) sim->set_end_time(sim->scenario().start_time + duration);
  std::unique_ptr<fleetmap::sim::OutputWriter> writer =
      fleetmap::sim::OutputWriter::Open(out_dir, *sim, &error, all_frames);
  if (!writer) {
    std::cerr << "fleetmap-sim: " << error << "\n";
    return 1;
  }
  const auto wall_start = std::chrono::steady_clock::now();
  auto last_report = wall_start;
  const double sim_start = sim->time();
  const bool tty = isatty(fileno(stderr));
  auto elapsed = [&wall_start]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  while (!sim->Done()) {
    if (!writer->Write(sim->Step(), &error)) {
      std::cerr << "\nfleetmap-sim: " << error << "\n";
      return 1;
    }
    const auto now = std::chrono::steady_clock::now();
    // On a terminal the line redraws every second; in a log, a line every 10 s.
    if (!quiet && now - last_report > std::chrono::seconds(tty ? 1 : 10)) {
      last_report = now;
      const double simulated = sim->time() - sim_start;
      const double total = sim->end_time() - sim_start;
      std::fprintf(stderr, "%s[fleetmap-sim] %s: %.1f / %.0f s simulated (%.0f%% max), %.1fx "
                   "real time   %s", tty ? "\r" : "", sim->scenario().name.c_str(), simulated, total,
                   100.0 * simulated / total, simulated / std::max(1e-9, elapsed()),
                   tty ? "" : "\n");
    }
  }
  if (!writer->Close(&error)) {
    std::cerr << "\nfleetmap-sim: " << error << "\n";
    return 1;
  }
  const double simulated = sim->time() - sim_start;
  std::fprintf(stderr, "%s[fleetmap-sim] %s: %zu robots, %.1f s simulated in %.1f s wall "
               "(%.1fx real time) -> %s\n", quiet || !tty ? "" : "\n", sim->scenario().name.c_str(),
               sim->robots().size(), simulated, elapsed(), simulated / std::max(1e-9, elapsed()),
               out_dir.c_str());
  return 0;
}

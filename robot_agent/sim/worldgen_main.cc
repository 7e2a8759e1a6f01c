// fleetmap-sim-worldgen: regenerates the shipped worlds (PGM + map YAML + world YAML) from code.
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world_designs.h"
#include "robot_agent/sim/world_io.h"

int main(int argc, char** argv) {
  CLI::App app{"Write the simulator's designed worlds as ROS map_server files."};
  std::string out_dir = fleetmap::sim::ShippedWorldsDir();
  std::vector<std::string> names = fleetmap::sim::DesignedWorldNames();
  app.add_option("--out", out_dir, "Output folder")->capture_default_str();
  app.add_option("--world", names, "World names (default: all)");
  CLI11_PARSE(app, argc, argv);
  for (const std::string& name : names) {
    fleetmap::sim::World world;
    if (!fleetmap::sim::MakeWorldByName(name, &world)) {
      std::cerr << "fleetmap-sim-worldgen: unknown world '" << name << "'\n";
      return 1;
    }
    std::string error;
    if (!fleetmap::sim::SaveWorld(out_dir, world, &error)) {
      std::cerr << "fleetmap-sim-worldgen: " << error << "\n";
      return 1;
    }
    std::cout << "wrote " << out_dir << "/" << name << ".{pgm,yaml,world.yaml} (" << world.width()
              << " x " << world.height() << " cells of " << world.resolution() << " m)\n";
  }
  return 0;
}

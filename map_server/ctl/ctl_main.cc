// fleetmapctl: the command-line client of the map server.
#include <iostream>

#include <CLI/CLI.hpp>

#include "map_server/ctl/ctl_commands.h"
#include "map_server/ctl/ctl_evaluate.h"
#include "map_server/server/map_server.h"

int main(int argc, char** argv) {
  CLI::App app{"fleetmapctl: inspect and export the fleetmap global map"};
  std::string server = "127.0.0.1:50051";
  fleetmap::CtlContext context;
  app.add_option("--server", server, "map server address, host:port")->capture_default_str();
  app.add_flag("--json", context.json, "print JSON instead of text");
  app.add_option("--timeout", context.timeout_seconds, "seconds to wait for the server")
      ->capture_default_str();
  app.require_subcommand(1);

  bool trajectories = false;
  auto* robots = app.add_subcommand("robots", "list robots, their placement and latest pose");
  robots->add_flag("--trajectories", trajectories, "include trajectories (JSON output)");

  fleetmap::ExportOptions export_options;
  auto* exporter = app.add_subcommand("export", "write the global map as PGM+YAML and PNG");
  exporter->add_option("--out", export_options.stem, "output path without extension")->required();
  auto* by_version = exporter->add_option("--version", export_options.version, "map version");
  exporter->add_option("--time", export_options.as_of_unix_time,
                       "newest version at or before this Unix time")
      ->excludes(by_version);
  exporter->add_option("--bbox", export_options.bbox, "min_x min_y max_x max_y (metres)")
      ->expected(4);
  exporter->add_option("--resolution", export_options.resolution, "metres per cell (0: native)");

  int limit = 20;
  auto* history = app.add_subcommand("history", "list versions with their provenance");
  history->add_option("--limit", limit, "how many, newest first")->capture_default_str();

  int64_t show_version = 0;
  auto* show = app.add_subcommand("show", "show one version in detail");
  show->add_option("version", show_version, "version (0: latest)")->required();

  int64_t before = 0, after = 0;
  std::string diff_png;
  auto* diff = app.add_subcommand("diff", "cells changed between two versions, and a picture");
  diff->add_option("v1", before, "older version")->required();
  diff->add_option("v2", after, "newer version")->required();
  diff->add_option("--out", diff_png, "PNG of the differences");

  fleetmap::EvaluateOptions evaluate_options;
  auto* evaluate = app.add_subcommand(
      "evaluate", "score the merge against ground truth (exit 2 while a robot is unplaced)");
  evaluate->add_option("--ground-truth", evaluate_options.ground_truth,
                       "YAML of true start poses (the simulator's manifest.yaml)")
      ->required();
  evaluate->add_option("--map", evaluate_options.map, "exported global map (YAML) to score");
  evaluate->add_option("--world", evaluate_options.world, "true world map (YAML)");
  evaluate->add_option("--tolerance-cells", evaluate_options.tolerance_cells,
                       "a map cell counts when a true wall cell is its own world cell or within "
                       "this many cells of it (along x and y)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10));
  evaluate->add_option("--localized", evaluate_options.localized,
                       "ROBOT=TRUE_TRAJECTORY: score a robot localizing in the global map against "
                       "its true poses (e.g. the simulator's robot1.gt.txt); repeatable");

  CLI11_PARSE(app, argc, argv);
  auto channel = fleetmap::MakeClientChannel(server);
  auto stub = fleetmap::v1::MapService::NewStub(channel);
  context.stub = stub.get();
  context.out = &std::cout;
  if (*robots) return fleetmap::RunRobots(context, trajectories);
  if (*exporter) return fleetmap::RunExport(context, export_options);
  if (*history) return fleetmap::RunHistory(context, limit);
  if (*show) return fleetmap::RunShow(context, show_version);
  if (*diff) return fleetmap::RunDiff(context, before, after, diff_png);
  if (*evaluate) return fleetmap::RunEvaluate(context, evaluate_options);
  return 1;
}

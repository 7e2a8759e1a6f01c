// fleetmap-merge-sim-bench: simulator scenarios (unknown start poses) through local SLAM and
// the MergeEngine in one process (no gRPC): relative transform error per robot pair, merged map
// vs the true world, false merges and the time to fold data in; with and without detections.
#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "map_server/bench/engine_flags.h"
#include "map_server/bench/merge_sim_diagnosis.h"
#include "map_server/bench/merge_sim_report.h"
#include "map_server/bench/merge_sim_run.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/slam/backend_factory.h"

int main(int argc, char** argv) {
  std::vector<std::string> scenarios = {"department_2robots", "department_3robots",
                                        "department_4robots", "building_2robots"};
  fleetmap::BenchOptions options;
  bool both = true;
  bool without_only = false;
  bool with_only = false;
  int seeds = 1;
  int first_seed = 0;
  CLI::App app{"merge benchmark: simulator scenarios -> local SLAM -> MergeEngine (in process)"};
  app.add_option("scenarios", scenarios, "scenario files or shipped scenario names")
      ->capture_default_str();
  app.add_flag("--no-detections", without_only, "only run without detections");
  app.add_flag("--detections-only", with_only, "only run with detections")
      ->excludes("--no-detections");
  app.add_flag("--verbose", options.verbose, "print every merge event");
  app.add_flag("--diagnose", options.diagnose, fleetmap::kDiagnoseHelp);
  app.add_flag(
      "--twins", options.twins,
      "print, for each robot pair with both maps at their true anchors (no local SLAM "
      "drift), the twin of the true alignment under the maps' symmetries (either map's, or "
      "all maps' together) that the "
      "whole-map check could least rule out: whether the maps alone can tell it from "
      "the truth");
  app.add_option("--feed-period", options.feed_period, "sim seconds between engine updates")
      ->capture_default_str();
  app.add_option("--detection-period", options.detection_period,
                 "sim seconds between two synthetic detections of one ordered pair (the agents' "
                 "camera runs at the scenario's camera rate, 5 Hz in the shipped ones)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--detection-sigma", options.detection_sigma,
                 "metres, standard deviation of the synthetic detections' noise along x and y "
                 "(the agents' camera + laser detector: 0.8-1.0 cm RMS, docs/BENCHMARKS.md)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--outliers", options.outlier_fraction,
                 "fraction of detections corrupted (moved by 1-5 m in a random direction)")
      ->capture_default_str();
  app.add_flag(
      "--no-mask", [&](int64_t) { options.mask_seen_robots = false; },
      "with detections: do not mask the returns off seen robots before local SLAM");
  app.add_flag(
      "--laser-bodies", options.mask_laser_bodies,
      "also mask the returns off round bodies the laser alone finds (with or without detections)");
  app.add_option("--laser-body-min-returns", options.laser_bodies.min_returns,
                 "fewest returns a round body found by the laser alone must have")
      ->capture_default_str();
  app.add_option("--algorithm", options.algorithm,
                 "every robot's local SLAM backend (the agent's default is scan-matching)")
      ->check(CLI::IsMember(fleetmap::LocalSlamAlgorithms()))
      ->capture_default_str();
  app.add_option("--submap-scans", options.submap_scans,
                 "scan-matching local SLAM: scans per submap (default: the backend's, 100)")
      ->check(CLI::Range(1, 100000));
  app.add_option(
         "--submap-travel", options.submap_travel,
         "scan-matching local SLAM: metres of travel per submap (default: the backend's, 10)")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--submap-resolution", options.submap_resolution,
                 "scan-matching local SLAM: the submaps' cell size, metres (default: the "
                 "backend's, 0.05)")
      ->check(CLI::Range(0.01, 1.0));
  app.add_flag("--settled-rebuild", options.settled_rebuild,
               "score a fresh engine fed every final submap, trajectory and detection at once "
               "(as the server rebuilds once uploads settle) instead of the engine fed as the "
               "run went, when it places at least as many robots");
  fleetmap::AddEngineFlags(&app, &options.engine);
  app.add_option("--seeds", seeds,
                 "runs per scenario, with the scenario's seed, then seed + 1, ... (a summary line "
                 "per scenario when more than one)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--first-seed", first_seed,
                 "offset of the first run's seed from the scenario's (held-out seeds: e.g. 8)")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (without_only) both = false;
  int false_merges = 0, false_as_fed = 0;
  for (const std::string& name : scenarios) {
    std::string path = name;
    if (path.find('/') == std::string::npos) {
      path = fleetmap::sim::ShippedScenariosDir() + "/" + name + ".yaml";
    }
    for (int with = both ? 1 : 0; with >= (with_only ? 1 : 0); --with) {
      options.detections = with == 1;
      const std::string mode =
          fleetmap::DetectionsMode(options.detections, options.outlier_fraction);
      std::vector<fleetmap::RunResult> runs;
      for (int k = first_seed; k < first_seed + seeds; ++k) {
        options.seed_offset = static_cast<uint64_t>(k);
        std::cout << name << " (" << mode << ")";
        if (seeds > 1 || first_seed > 0) std::cout << ", seed +" << k;
        std::cout << ": running..." << std::endl;
        fleetmap::RunResult result;
        std::string error;
        const auto start = std::chrono::steady_clock::now();
        if (!fleetmap::Run(path, options, &result, &error)) {
          std::cerr << "fleetmap-merge-sim-bench: " << name << ": " << error << "\n";
          return 1;
        }
        const auto elapsed = std::chrono::steady_clock::now() - start;
        fleetmap::PrintRun(result, std::chrono::duration<double>(elapsed).count());
        false_merges += result.false_merges;
        false_as_fed += result.false_merges_as_fed;
        runs.push_back(std::move(result));
      }
      fleetmap::PrintSummary(name, mode, runs);
    }
  }
  std::cout << "total false merges: " << false_merges
            << " (pairs placed wrong at some point as the runs went, withdrawn or not: "
            << false_as_fed << ")" << std::endl;
  return 0;
}

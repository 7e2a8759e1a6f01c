// slam_comparison: the local SLAM comparison of issue 4 (item 5). Runs every available backend on
// the simulator scenarios of the paper's table I (in process) and on the public benchmark logs
// found in the data directory, and prints markdown tables: rectangle size measured on the map,
// end-point error and ATE for the scenarios; relations error (Kümmerle et al. 2009), time and
// speed for the logs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <filesystem>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "robot_agent/bench/map_extent.h"
#include "robot_agent/bench/sim_slam_run.h"
#include "robot_agent/slam/backend_factory.h"
#include "robot_agent/slam/submap_assembly.h"
#include "shared/eval/absolute_trajectory_error.h"
#include "robot_agent/slam/log_runner.h"
#include "shared/eval/relations_file.h"
#include "shared/eval/relations_metric.h"

namespace fleetmap {
namespace {

struct BenchLog {
  std::string name;
  std::string log;        // relative to the data directory
  std::string relations;  // relative to the data directory
};

struct BenchScenario {
  std::string name;
  // The rectangle's outer walls as the laser sees them (inner faces: the world's 21.3 m x 17 m
  // outer walls are 0.2 m thick); zero for scenarios without a size to measure.
  Eigen::Vector2d real_size = Eigen::Vector2d::Zero();
};

std::unique_ptr<LocalSlam> MakeBackend(BackendChoice choice, const std::string& algorithm) {
  choice.algorithm = algorithm;
  std::string error;
  std::unique_ptr<LocalSlam> slam = MakeLocalSlam(choice, &error);
  if (!slam) std::cerr << "error: " << error << "\n";
  return slam;
}

// Every return of `run` at the poses of `poses` (one per scan, as `run.ground_truth`), moved by
// `world_from_poses`; empty when the poses do not match the scans one to one.
std::vector<Eigen::Vector2d> WorldReturns(const SimSlamRun& run, const Trajectory& poses,
                                          const Rigid2d& world_from_poses) {
  std::vector<Eigen::Vector2d> points;
  if (poses.size() != run.returns.size() || poses.size() != run.ground_truth.size()) return points;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (std::abs(poses[i].timestamp - run.ground_truth[i].timestamp) > 1e-6) return {};
    const Rigid2d robot_in_world = world_from_poses * poses[i].pose;
    for (const Eigen::Vector2f& p : run.returns[i]) points.push_back(robot_in_world * Eigen::Vector2d(p.cast<double>()));
  }
  return points;
}

// Table I: the simulator scenarios. Returns false on an error.
bool RunScenarios(const std::string& scenarios_dir, const std::vector<std::string>& names,
                  const std::vector<std::string>& algorithms, const BackendChoice& base) {
  std::printf("| scenario | backend | real L x H (m) | measured L x H (m) | L / H error | on the map's cells | end-point error (m) | ATE RMSE (m, deg) | time (s) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& name : names) {
    BenchScenario scenario{name};
    if (name.rfind("rectangle", 0) == 0) scenario.real_size = Eigen::Vector2d(20.9, 16.6);
    // The size a perfect SLAM reads (every scan at its true pose), on the returns and on the
    // map's cells (centres on a 5 cm grid).
    std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> size_at_true_poses;
    for (const std::string& algorithm : algorithms) {
      std::unique_ptr<LocalSlam> slam = MakeBackend(base, algorithm);
      if (!slam) return false;
      std::cerr << "running " << algorithm << " on scenario " << name << "\n";
      SimSlamRun run;
      std::string error;
      std::optional<OccupancyGrid> truth_map;
      if (scenario.real_size.x() > 0.0 && !size_at_true_poses) truth_map.emplace(OccupancyGridOptions());
      if (!RunSimulatedScenario(scenarios_dir + "/" + name + ".yaml", slam.get(), &run, &error,
                                truth_map ? &*truth_map : nullptr)) {
        std::cerr << "error: " << name << ": " << error << "\n";
        return false;
      }
      std::cerr << "  " << slam->Statistics() << "\n";
      AteOptions ate_options;
      ate_options.align = true;
      ate_options.max_time_difference = 1e-6;
      const std::optional<AteResult> ate = EvaluateAte(run.estimate, run.ground_truth, ate_options);
      // End point: the final pose relative to the first, against the truth's.
      const Rigid2d estimated = run.estimate.front().pose.inverse() * run.estimate.back().pose;
      const Rigid2d truth = run.ground_truth.front().pose.inverse() * run.ground_truth.back().pose;
      const double end_error = (estimated.translation() - truth.translation()).norm();
      std::string real = "-", measured = "-", size_error = "-", cell_error = "-";
      if (scenario.real_size.x() > 0.0 && ate) {
        const Eigen::Vector2d& real_size = scenario.real_size;
        const auto format_error = [&](const Eigen::Vector2d& size) {
          char text[64];
          std::snprintf(text, sizeof(text), "%.2f %% / %.2f %%",
                        100.0 * std::abs(size.x() - real_size.x()) / real_size.x(),
                        100.0 * std::abs(size.y() - real_size.y()) / real_size.y());
          return std::string(text);
        };
        char text[160];
        std::snprintf(text, sizeof(text), "%.2f x %.2f", real_size.x(), real_size.y());
        real = text;
        // On the returns at the estimated poses (brought into the world by the ATE alignment):
        // the walls where the map draws them, without its cells' quantisation.
        if (const auto extent = MeasureOuterWalls(WorldReturns(run, run.estimate, ate->ground_truth_from_estimate))) {
          std::snprintf(text, sizeof(text), "%.3f x %.3f", extent->size().x(), extent->size().y());
          measured = text;
          size_error = format_error(extent->size());
        }
        // The same on the map's occupied cells, as the paper reads its maps.
        std::vector<const Submap*> submaps;
        for (const auto& [id, submap] : run.submaps) submaps.push_back(&submap);
        const OccupancyGrid map = AssembleSubmaps(submaps, OccupancyGridOptions());
        if (const auto extent = MeasureOuterWalls(map, ate->ground_truth_from_estimate)) {
          cell_error = format_error(extent->size());
        }
        // What a perfect SLAM reads, each way: the measurements' own floor, once per scenario.
        if (truth_map) {
          const auto on_cells = MeasureOuterWalls(*truth_map, Rigid2d());
          const auto on_returns = MeasureOuterWalls(WorldReturns(run, run.ground_truth, Rigid2d()));
          if (on_cells && on_returns) size_at_true_poses = {on_returns->size(), on_cells->size()};
        }
        if (size_at_true_poses) {
          std::snprintf(text, sizeof(text), " (true poses: %.3f x %.3f; cells %.3f x %.3f)",
                        size_at_true_poses->first.x(), size_at_true_poses->first.y(),
                        size_at_true_poses->second.x(), size_at_true_poses->second.y());
          real += text;
        }
      }
      char ate_text[64] = "-";
      if (ate) std::snprintf(ate_text, sizeof(ate_text), "%.3f, %.2f", ate->rmse_translation, ate->rmse_rotation_deg);
      std::printf("| %s | %s | %s | %s | %s | %s | %.3f | %s | %.2f |\n", name.c_str(),
                  algorithm.c_str(), real.c_str(), measured.c_str(), size_error.c_str(),
                  cell_error.c_str(), end_error, ate_text, run.slam_seconds);
      std::fflush(stdout);
    }
  }
  return true;
}

int Run(int argc, char** argv) {
  CLI::App app{"Runs the local SLAM backends on the simulator scenarios of the paper's table I and "
               "on intel and aces, and prints markdown tables (map size, end-point error, ATE; "
               "relations error, time and speed)."};
  std::string data_dir = "../shared/data";
  std::vector<std::string> algorithms = LocalSlamAlgorithms();
  app.add_option("--data", data_dir, "Directory of the public data sets")->capture_default_str();
  app.add_option("--algorithms", algorithms, "Backends to run")->capture_default_str();
  std::string scenarios_dir = FLEETMAP_SIM_SCENARIOS_DIR;
  std::vector<std::string> scenarios = {"rectangle_1lap", "rectangle_3laps", "department_lab1_lab2_lab1",
                                        "building_1lap"};
  bool skip_logs = false;
  app.add_option("--scenarios-dir", scenarios_dir, "Folder of the simulator scenarios")->capture_default_str();
  app.add_option("--scenarios", scenarios, "Simulator scenarios to run (none: --scenarios '')")
      ->capture_default_str();
  app.add_flag("--skip-logs", skip_logs, "Only run the simulator scenarios");
  BackendChoice base;
  app.add_option("--particles", base.particles, "Particle count (particle filter backends)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--seed", base.seed, "Random seed (particle filter backends)")->capture_default_str();
  app.add_option("--motion", base.motion,
                 "Particle filter backends: motion input, odometry (the paper's pseudo-code) or "
                 "scan-matched (default)")
      ->check(CLI::IsMember(ParticleMotionInputs()));
  app.add_option("--particle-loop-closure", base.particle_loop_closure,
                 "Particle filter backends: global loop closure over the best particle (on|off)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  scenarios.erase(std::remove(scenarios.begin(), scenarios.end(), std::string()), scenarios.end());
  if (!scenarios.empty()) {
    if (!RunScenarios(scenarios_dir, scenarios, algorithms, base)) return 1;
    std::printf("\n");
  }
  if (skip_logs) return 0;

  const std::vector<BenchLog> logs = {
      {"intel", "intel-lab/intel.clf.bz2", "intel-lab/intel.relations"},
      {"aces", "aces/aces.clf.bz2", "aces/aces.relations"},
  };
  std::printf("| log | backend | relations | trans. error (m) | rot. error (deg) | time (s) | scans/s | x real time |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  int ran = 0;
  for (const BenchLog& bench : logs) {
    const std::string log_path = data_dir + "/" + bench.log;
    const std::string relations_path = data_dir + "/" + bench.relations;
    if (!std::filesystem::exists(log_path) || !std::filesystem::exists(relations_path)) {
      std::cerr << "skipping " << bench.name << ": " << log_path << " or its relations not found\n";
      continue;
    }
    std::string error;
    SlamLog log;
    std::vector<Relation> relations;
    if (!LoadSlamLog(log_path, SlamLogOptions(), &log, &error) ||
        !ReadRelations(relations_path, &relations, &error)) {
      std::cerr << "error: " << error << "\n";
      return 1;
    }
    const double duration = log.scans.back().timestamp - log.scans.front().timestamp;
    for (const std::string& algorithm : algorithms) {
      std::unique_ptr<LocalSlam> slam = MakeBackend(base, algorithm);
      if (!slam) return 1;
      std::cerr << "running " << algorithm << " on " << bench.name << " (" << log.scans.size() << " scans)\n";
      SlamRunResult result;
      if (!RunSlam(log, slam.get(), &result, &error)) {
        std::cerr << "error: " << bench.name << ": " << error << "\n";
        return 1;
      }
      std::cerr << "  " << slam->Statistics() << "\n";
      const RelationsResult metric = EvaluateRelations(result.trajectory, relations);
      std::printf("| %s | %s | %d (%d unmatched) | %.3f ± %.3f | %.2f ± %.2f | %.2f | %.0f | %.0f |\n",
                  bench.name.c_str(), algorithm.c_str(), metric.used, metric.skipped,
                  metric.translation.mean, metric.translation.std, metric.rotation_deg.mean,
                  metric.rotation_deg.std, result.seconds,
                  static_cast<double>(log.scans.size()) / result.seconds, duration / result.seconds);
      std::fflush(stdout);
      ++ran;
    }
  }
  if (ran == 0) {
    std::cerr << "error: no benchmark log found under " << data_dir << "\n";
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }

// fleetmap-slam: builds a map and a per-scan trajectory from a CARMEN log with one of the local
// SLAM backends.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "robot_agent/slam/backend_factory.h"
#include "robot_agent/slam/log_runner.h"
#include "robot_agent/slam/submap_assembly.h"
#include "shared/io/map_file.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap {
namespace {

int Fail(const std::string& message) {
  std::cerr << "fleetmap-slam: error: " << message << "\n";
  return 1;
}

int Run(int argc, char** argv) {
  CLI::App app{"Builds a map (map.pgm/.yaml/.png) and a trajectory with one pose per laser scan "
               "(trajectory.txt, 'timestamp x y theta', ipc_timestamp) from a CARMEN log."};
  BackendChoice choice;
  std::string log_path, out_dir;
  SlamLogOptions log_options;
  double resolution = 0.05;
  bool quiet = false;
  std::string algorithms;
  for (const std::string& name : LocalSlamAlgorithms()) algorithms += (algorithms.empty() ? "" : ", ") + name;
  app.add_option("--algorithm", choice.algorithm, "Local SLAM backend: " + algorithms)
      ->capture_default_str();
  app.add_option("--log", log_path, "CARMEN log (.clf/.log, plain, .gz or .bz2)")->required();
  app.add_option("--out", out_dir, "Output directory (created if missing)")->required();
  app.add_option("--resolution", resolution, "Resolution of the written map (metres per cell)")
      ->capture_default_str()->check(CLI::Range(0.005, 1.0));
  app.add_option("--particles", choice.particles, "Particle count (particle filter backends)")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  app.add_option("--seed", choice.seed, "Random seed (particle filter backends)")->capture_default_str();
  app.add_option("--motion", choice.motion,
                 "Particle filter backends: motion input, odometry (the paper's pseudo-code) or "
                 "scan-matched (default)")
      ->check(CLI::IsMember(ParticleMotionInputs()));
  app.add_option("--particle-loop-closure", choice.particle_loop_closure,
                 "Particle filter backends: global loop closure over the best particle (on|off)")
      ->capture_default_str();
  app.add_flag("--skip-out-of-order", log_options.skip_out_of_order,
               "Drop scans older than the scan before them instead of failing");
  app.add_flag("--skip-bad-lines", log_options.skip_bad_lines,
               "Skip malformed log lines instead of failing");
  app.add_flag("--quiet", quiet, "No progress output");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  std::unique_ptr<LocalSlam> slam = MakeLocalSlam(choice, &error);
  if (!slam) return Fail(error);

  const auto read_start = std::chrono::steady_clock::now();
  SlamLog log;
  if (!LoadSlamLog(log_path, log_options, &log, &error)) return Fail(error);
  const double read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
  const double duration = log.scans.back().timestamp - log.scans.front().timestamp;
  if (!quiet) {
    std::cerr << "read " << log.scans.size() << " scans (" << duration << " s of data) in "
              << read_seconds << " s; odometry from " << log.odometry_source << "\n";
  }
  for (const std::string& warning : log.warnings) std::cerr << "fleetmap-slam: warning: " << warning << "\n";

  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec || !std::filesystem::is_directory(out_dir)) {
    return Fail("cannot create output directory '" + out_dir + "': " + ec.message());
  }

  SlamRunResult result;
  auto progress = [&](size_t done, size_t total) {
    if (quiet) return;
    std::fprintf(stderr, "\r%s: %zu / %zu scans (%3.0f%%)%s", choice.algorithm.c_str(), done, total,
                 100.0 * static_cast<double>(done) / static_cast<double>(total),
                 done == total ? "; finishing (last submap, final loop closure)" : "");
    std::fflush(stderr);
  };
  if (!RunSlam(log, slam.get(), &result, &error, progress)) return Fail(error);
  if (!quiet) std::cerr << "\n" << slam->Statistics() << "\n";
  slam.reset();  // its maps are no longer needed while the submaps are unpacked

  OccupancyGridOptions grid_options;
  grid_options.resolution = resolution;
  OccupancyGrid map(grid_options);
  // One submap unpacked at a time: all at once took 109 MB for FastSLAM's 252 on intel.
  for (const auto& [id, packed] : result.submaps) AddSubmapToAssembly(UnpackSubmap(packed), &map);
  if (!WriteMap(out_dir + "/map", map, &error)) return Fail(error);
  if (!WriteMapPng(out_dir + "/map.png", map, &error)) return Fail(error);
  if (!WriteTrajectory(out_dir + "/trajectory.txt", result.trajectory, &error)) return Fail(error);

  const double scans_per_second = static_cast<double>(log.scans.size()) / std::max(1e-9, result.seconds);
  std::printf("%s: %zu scans in %.2f s: %.0f scans/s, %.0fx real time; %zu submaps; wrote %s/map.pgm, "
              "map.yaml, map.png, trajectory.txt\n",
              choice.algorithm.c_str(), log.scans.size(), result.seconds, scans_per_second,
              duration / std::max(1e-9, result.seconds), result.submaps.size(), out_dir.c_str());
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }

// fleetmap-localize: replays MRCLAM or simulator runs (and measures the filter's update rate)
// to report localization error over time, time to converge, and a PNG plot of error vs time.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "robot_agent/localization/tool/error_plot.h"
#include "robot_agent/localization/tool/log_command.h"
#include "robot_agent/localization/tool/mrclam_reader.h"
#include "robot_agent/localization/tool/mrclam_replay.h"
#include "robot_agent/localization/tool/rate_benchmark.h"
#include "robot_agent/localization/tool/sim_command.h"

namespace fleetmap {
namespace {

void PrintResult(const char* label, const ReplayResult& result) {
  std::printf("%s: mean position error over all robots %.3f m\n", label,
              result.mean_position_error);
  std::printf("  %-7s %10s %10s %12s %9s %9s\n", "robot", "mean [m]", "mean [deg]",
              "converge [s]", "detected", "used");
  for (const RobotReplayResult& r : result.robots) {
    std::printf("  %-7s %10.3f %10.2f %12.1f %9d %9d\n", r.name.c_str(), r.mean_position_error,
                r.mean_heading_error * 180.0 / M_PI, r.time_to_converge, r.detections_made,
                r.detections_used);
  }
}

bool Plot(const std::string& path, const ReplayResult& result, double max_error) {
  std::vector<ErrorSeries> series;
  for (const RobotReplayResult& r : result.robots) series.push_back(r.position_error);
  ErrorPlotOptions plot;
  plot.max_error = max_error;
  std::string error;
  if (!WriteErrorPlot(path, series, plot, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return false;
  }
  std::printf("wrote %s (x: time, grid every %.0f s; y: position error 0..%.2f m, grid every "
              "%.2f m; colours:",
              path.c_str(), TickStep(series.empty() || series[0].points.empty()
                                         ? 1.0
                                         : series[0].points.back().first,
                                     10),
              max_error, TickStep(max_error, 8));
  for (size_t i = 0; i < series.size(); ++i) {
    std::printf(" %s=%s", series[i].name.c_str(), kPlotColourNames[i % 6]);
  }
  std::printf(")\n");
  return true;
}

int RunMrclam(const std::string& data, int robots, const std::string& mode,
              LocalizationReplayOptions options, const std::string& plot_prefix,
              double plot_max_error) {
  MrclamDataset dataset;
  std::string error;
  std::printf("reading %s ...\n", data.c_str());
  if (!ReadMrclam(data, robots, &dataset, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  std::printf("%zu robots, %zu landmarks, %zu odometry rows per robot; start %s\n",
              dataset.robots.size(), dataset.landmarks.size(),
              dataset.robots.front().odometry.size(),
              options.known_start ? "known (Gaussian around the true start)" : "uniform");
  const std::vector<bool> runs =
      mode == "both" ? std::vector<bool>{false, true} : std::vector<bool>{mode == "collaborative"};
  std::vector<ReplayResult> results;
  for (const bool collaborative : runs) {
    options.collaborative = collaborative;
    const char* label = collaborative ? "collaborative" : "independent";
    const auto start = std::chrono::steady_clock::now();
    const ReplayResult result = ReplayMrclam(dataset, options, [&](double t) {
      std::fprintf(stderr, "\r%s: t = %.0f s", label, t);
    });
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "\n");
    PrintResult(label, result);
    std::printf("  (%.1f s wall)\n", seconds);
    if (!plot_prefix.empty() &&
        !Plot(plot_prefix + "_" + label + ".png", result, plot_max_error)) {
      return 1;
    }
    results.push_back(result);
  }
  if (results.size() == 2) {
    const double a = results[0].mean_position_error, b = results[1].mean_position_error;
    std::printf("collaborative vs independent: %.3f m vs %.3f m (%+.1f %%)\n", b, a,
                a > 0 ? 100.0 * (b - a) / a : 0.0);
    for (size_t r = 0; r < results[0].robots.size(); ++r) {
      std::printf("  %s: %.3f -> %.3f m\n", results[0].robots[r].name.c_str(),
                  results[0].robots[r].mean_position_error,
                  results[1].robots[r].mean_position_error);
    }
  }
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) {
  using namespace fleetmap;
  CLI::App app{"Monte Carlo localization replays: MRCLAM and the simulator with and without the "
               "collaborative detection update, and the filter's update rate."};
  app.require_subcommand(1);

  CLI::App* mrclam = app.add_subcommand("mrclam", "Localize every MRCLAM robot");
  std::string data = "../shared/data/utias-mrclam/resampled_50Hz_full_groundtruth";
  int robots = 5;
  std::string mode = "both", start = "known", plot_prefix;
  double plot_max_error = 1.0;
  LocalizationReplayOptions options;
  mrclam->add_option("--data", data, "Folder of the resampled MRCLAM set")->capture_default_str();
  mrclam->add_option("--robots", robots, "Robots 1..N")->capture_default_str()->check(CLI::Range(1, 5));
  mrclam->add_option("--mode", mode, "independent | collaborative | both")
      ->capture_default_str()
      ->check(CLI::IsMember({"independent", "collaborative", "both"}));
  mrclam->add_option("--start", start, "known | uniform")
      ->capture_default_str()
      ->check(CLI::IsMember({"known", "uniform"}));
  mrclam->add_option("--particles", options.particles, "Maximum particles per robot")
      ->capture_default_str()
      ->check(CLI::Range(10, 100000));
  mrclam->add_option("--seed", options.seed, "Random seed")->capture_default_str();
  mrclam->add_option("--max-time", options.max_time, "Stop after this log time (s), 0 = all")
      ->capture_default_str();
  mrclam->add_option("--max-injection", options.mcl.recovery.max_injection_fraction,
                     "Augmented MCL: most random particles per resampling (0 = off)")
      ->capture_default_str();
  mrclam
      ->add_option("--lost-detection-interval", options.lost_detection_interval,
                   "Seconds between detections used per robot pair while the observed robot is "
                   "globally localizing (otherwise 2 s)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  mrclam->add_option("--sigma-range", options.landmarks.sigma_range)->capture_default_str();
  mrclam->add_option("--sigma-bearing", options.landmarks.sigma_bearing)->capture_default_str();
  mrclam->add_option("--plot", plot_prefix, "Write <prefix>_<mode>.png plots of error vs time");
  mrclam->add_option("--plot-max-error", plot_max_error, "Top of the plot's error axis (m)")
      ->capture_default_str();

  CLI::App* rate = app.add_subcommand("rate", "Measure MCL laser updates per second");
  RateBenchmarkOptions rate_options;
  rate->add_option("--particles", rate_options.particles)->capture_default_str();
  rate->add_option("--beams", rate_options.beams, "Beams used of the 181")->capture_default_str();
  rate->add_option("--updates", rate_options.updates)->capture_default_str();

  CLI::App* sim = app.add_subcommand(
      "sim", "The paper's Fig. 21-22 case in the simulator: a lost robot (uniform belief) seen by "
             "a robot with a known start; seeded runs with and without detections");
  SimCommandOptions sim_options;
  sim_options.scenario_path =
      std::string(FLEETMAP_LOCALIZATION_SCENARIOS_DIR) + "/department_fig22.yaml";
  SimLocalizationOptions& sim_loc = sim_options.localization;
  sim->add_option("--scenario", sim_options.scenario_path, "Simulator scenario (fleetmap-sim YAML)")
      ->capture_default_str();
  sim->add_option("--runs", sim_options.runs, "Seeded runs (simulator seed = scenario seed + run)")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  sim->add_option("--seed", sim_options.first_seed, "Filter seed of run 0")->capture_default_str();
  sim->add_option("--mode", sim_options.mode, "collaborative | independent | both")
      ->capture_default_str()
      ->check(CLI::IsMember({"independent", "collaborative", "both"}));
  sim->add_option("--lost-robot", sim_loc.lost_robot, "Index of the robot with a uniform belief")
      ->capture_default_str();
  sim->add_option("--particles", sim_loc.particles, "Maximum particles per robot")
      ->capture_default_str()
      ->check(CLI::Range(10, 100000));
  sim->add_option("--max-time", sim_loc.max_time,
                  "Stop each run at this time (s), 0 = scenario end")
      ->capture_default_str();
  sim->add_option("--detection-interval", sim_loc.detection_interval,
                  "Seconds between detections used per robot pair (DetectionGate)")
      ->capture_default_str();
  sim->add_option("--lost-detection-interval", sim_loc.lost_detection_interval,
                  "The same while the observed robot is globally localizing (its belief not yet "
                  "confirmed by a detection)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  sim->add_option("--lost-floor", sim_loc.density.lost_belief_floor_probability,
                  "Belief floor of a globally localizing robot in the detection update")
      ->capture_default_str();
  sim->add_option("--hold", sim_loc.hold_time, "Seconds the error must stay within tolerance")
      ->capture_default_str();
  sim->add_option("--trace", sim_options.trace_run, "Print the lost robot's errors of this run")
      ->capture_default_str();
  sim->add_option("--plot", sim_options.plot_path, "PNG of error vs time of run 0");
  sim->add_option("--plot-max-error", sim_options.plot_max_error, "Top of the error axis (m)")
      ->capture_default_str();

  CLI::App* log_command = app.add_subcommand(
      "log",
      "The agent's localizer over a CARMEN log in a known map (e.g. the map fleetmap-slam "
      "made of the same log): one pose per scan to a trajectory file");
  LogCommandOptions log_options;
  std::vector<double> initial_pose;
  log_command->add_option("--log", log_options.log_path, "CARMEN log (plain, .gz or .bz2)")
      ->required()
      ->check(CLI::ExistingFile);
  log_command->add_option("--map", log_options.map_path, "ROS map (YAML + image)")
      ->required()
      ->check(CLI::ExistingFile);
  log_command->add_option("--out", log_options.out_path, "Trajectory file to write")->required();
  log_command
      ->add_option("--initial-pose", initial_pose,
                   "x y theta of the first scan in the map (m, m, rad); without it the robot "
                   "localizes globally")
      ->expected(3);
  log_command
      ->add_option("--initial-std", log_options.localizer.initial_position_std,
                   "Position std around --initial-pose (m)")
      ->capture_default_str();
  log_command
      ->add_option("--particles", log_options.localizer.mcl.kld.max_particles, "Maximum particles")
      ->capture_default_str()
      ->check(CLI::Range(10, 1000000));
  log_command
      ->add_option("--beams", log_options.localizer.laser.max_beams, "Laser returns per update")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  log_command
      ->add_option("--update-min-translation", log_options.localizer.update_min_translation,
                   "Motion (m) between laser corrections; odometry carries the pose in between")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  log_command
      ->add_option("--update-min-rotation", log_options.localizer.update_min_rotation,
                   "Or this rotation (rad)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  log_command
      ->add_option("--update-max-interval", log_options.localizer.update_max_interval,
                   "Or this long since the previous correction (s; 0: never on time alone)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  log_command
      ->add_option("--scan-seeding", log_options.localizer.seeding.enabled,
                   "After a global start, move some particles to where a scan-to-map search "
                   "fits the scan best (true/false)")
      ->capture_default_str();
  log_command
      ->add_option("--max-injection", log_options.localizer.mcl.recovery.max_injection_fraction,
                   "Augmented MCL: most random particles per resampling (0 = off)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  log_command
      ->add_option("--random-injection", log_options.localizer.mcl.recovery.enabled,
                   "Augmented MCL's random injection (kidnap recovery), off as in AMCL")
      ->capture_default_str();
  log_command->add_option("--seed", log_options.localizer.mcl.seed, "Random seed")
      ->capture_default_str();
  log_command
      ->add_option("--max-range", log_options.max_range,
                   "Readings at or above it are no-returns (m)")
      ->capture_default_str();

  CLI11_PARSE(app, argc, argv);
  if (sim->parsed()) return RunSimCommand(sim_options);
  if (log_command->parsed()) {
    if (!initial_pose.empty()) {
      log_options.localizer.initial_pose =
          Rigid2d(initial_pose[0], initial_pose[1], initial_pose[2]);
    }
    log_options.localizer.mcl.kld.min_particles = std::min(
        log_options.localizer.mcl.kld.min_particles, log_options.localizer.mcl.kld.max_particles);
    return RunLogCommand(log_options);
  }
  if (mrclam->parsed()) {
    options.known_start = start == "known";
    return RunMrclam(data, robots, mode, options, plot_prefix, plot_max_error);
  }
  const RateBenchmarkResult r = RunRateBenchmark(rate_options);
  std::printf("%d particles, %d of 181 beams, one core: %d updates (predict + laser) in %.3f s "
              "= %.1f updates/s; %.1f updates/s when also resampling after every update\n",
              rate_options.particles, rate_options.beams, rate_options.updates, r.seconds,
              r.updates_per_second, r.updates_per_second_with_resampling);
  return 0;
}

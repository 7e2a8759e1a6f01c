#include "robot_agent/localization/tool/sim_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "robot_agent/sim/world_io.h"
#include "shared/io/map_file.h"

namespace fleetmap {
namespace {

struct Summary {
  int runs = 0;
  int successes = 0;
  int with_detection = 0;
  int localized = 0;
  std::vector<double> delays;  // collaborative: localized - first detection; else: from start
};

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return -1.0;
  std::sort(values.begin(), values.end());
  const size_t i = std::min(values.size() - 1, static_cast<size_t>(q * (values.size() - 1) + 0.5));
  return values[i];
}

void PrintDelays(const char* what, const std::vector<double>& delays) {
  if (delays.empty()) {
    std::printf("  %s: none\n", what);
    return;
  }
  double sum = 0.0;
  for (const double d : delays) sum += d;
  std::printf("  %s: median %.2f s, mean %.2f s, 90th percentile %.2f s, max %.2f s (%zu runs)\n",
              what, Percentile(delays, 0.5), sum / delays.size(), Percentile(delays, 0.9),
              *std::max_element(delays.begin(), delays.end()), delays.size());
}

void PrintTrace(const SimRobotResult& robot, bool collaborate) {
  std::printf("\n  %s %s: time [s] position error [m] heading error [deg]\n", robot.name.c_str(),
              collaborate ? "with detections" : "alone");
  double next = 0.0;
  for (size_t i = 0; i < robot.position_error.points.size(); ++i) {
    const double t = robot.position_error.points[i].first;
    if (t + 1e-9 < next) continue;
    next = t + 0.5;
    std::printf("  %6.1f %8.3f %8.2f\n", t, robot.position_error.points[i].second,
                robot.heading_error.points[i].second * 180.0 / M_PI);
  }
}

// Adds one run to the summary and prints its columns of the table row.
void Tally(const SimRunResult& result, const SimRobotResult& lost, bool collaborate,
           double target_delay, Summary* summary) {
  ++summary->runs;
  if (!collaborate) {
    if (lost.time_localized >= 0.0) {
      ++summary->localized;
      summary->delays.push_back(lost.time_localized);
    }
    std::printf(" %9.2f %6s", lost.time_localized, lost.localized_at_end ? "yes" : "no");
    return;
  }
  const double first = result.first_detection_time;
  double delay = -1.0;
  if (first >= 0.0) {
    ++summary->with_detection;
    // Localized before the detection (by its own laser) counts as no delay.
    if (lost.time_localized >= 0.0) delay = std::max(0.0, lost.time_localized - first);
  }
  if (delay >= 0.0) {
    ++summary->localized;
    summary->delays.push_back(delay);
    if (delay <= target_delay) ++summary->successes;
  }
  std::printf(" %9.1f %9.2f %9.2f %6s |", first, lost.time_localized, delay,
              lost.localized_at_end ? "yes" : "no");
}

void PrintSummary(const Summary& collaborative, const Summary& independent,
                  double target_delay) {
  if (collaborative.runs > 0) {
    std::printf("with detections: %d of %d runs had a detection of the lost robot; localized "
                "within %.1f s of the first detection in %d of %d runs (%.1f %%); localized "
                "at all in %d\n",
                collaborative.with_detection, collaborative.runs, target_delay,
                collaborative.successes, collaborative.runs,
                100.0 * collaborative.successes / collaborative.runs, collaborative.localized);
    PrintDelays("time from first detection to localized", collaborative.delays);
  }
  if (independent.runs > 0) {
    std::printf("without detections: localized in %d of %d runs (not localized by the end of "
                "the run in %d)\n",
                independent.localized, independent.runs, independent.runs - independent.localized);
    PrintDelays("time from start to localized", independent.delays);
  }
}

bool WritePlot(const SimCommandOptions& options, const std::vector<ErrorSeries>& series) {
  ErrorPlotOptions plot;
  plot.max_error = options.plot_max_error;
  std::string error;
  if (!WriteErrorPlot(options.plot_path, series, plot, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return false;
  }
  const double end = series.empty() || series[0].points.empty() ? 1.0
                                                                : series[0].points.back().first;
  std::printf("wrote %s (run 0; x: time, grid every %.0f s; y: position error 0..%.2f m, grid "
              "every %.2f m, clipped; colours:",
              options.plot_path.c_str(), TickStep(end, 10), options.plot_max_error,
              TickStep(options.plot_max_error, 8));
  for (size_t i = 0; i < series.size(); ++i) {
    std::printf(" %s=%s", series[i].name.c_str(), kPlotColourNames[i % 6]);
  }
  std::printf(")\n");
  return true;
}

}  // namespace

int RunSimCommand(const SimCommandOptions& options) {
  sim::Scenario scenario;
  sim::World world;
  OccupancyGrid map;
  std::string error;
  if (!sim::LoadScenario(options.scenario_path, &scenario, &error) ||
      !sim::LoadWorld(scenario.world_path, &world, &error) ||
      !LoadWorldMap(scenario.world_path, &map, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  const SimLocalizationOptions& base = options.localization;
  if (base.lost_robot < 0 || static_cast<size_t>(base.lost_robot) >= scenario.robots.size()) {
    std::fprintf(stderr, "error: --lost-robot %d: the scenario has %zu robots\n", base.lost_robot,
                 scenario.robots.size());
    return 1;
  }
  std::vector<bool> modes;  // true = collaborative
  if (options.mode != "independent") modes.push_back(true);
  if (options.mode != "collaborative") modes.push_back(false);
  std::printf("%s: world %s, %zu robots, lost robot %s (uniform over %s), %d runs, %d particles "
              "max; detections simulated from ground-truth visibility (range <= %.1f m) with "
              "noise %.3f m / %.2f deg\n",
              scenario.name.c_str(), scenario.world.c_str(), scenario.robots.size(),
              scenario.robots[static_cast<size_t>(base.lost_robot)].name.c_str(),
              scenario.world.c_str(), options.runs, base.particles, base.detection_max_range,
              base.range_std, base.bearing_std * 180.0 / M_PI);
  std::printf("localized = estimate within %.2f m / %.1f deg for >= %.1f s\n",
              base.position_tolerance, base.heading_tolerance * 180.0 / M_PI, base.hold_time);
  std::printf("%4s %6s |", "run", "seed");
  if (options.mode != "independent") {
    std::printf(" %9s %9s %9s %6s |", "1st det", "localized", "delay", "end ok");
  }
  if (options.mode != "collaborative") std::printf(" %9s %6s", "alone", "end ok");
  std::printf("\n");
  Summary collaborative, independent;
  std::vector<ErrorSeries> plot_series;
  const auto start = std::chrono::steady_clock::now();
  for (int run = 0; run < options.runs; ++run) {
    sim::Scenario seeded = scenario;
    seeded.seed = scenario.seed + static_cast<uint64_t>(run);
    std::printf("%4d %6llu |", run, static_cast<unsigned long long>(seeded.seed));
    for (const bool collaborate : modes) {
      SimLocalizationOptions localization = base;
      localization.detections = collaborate;
      localization.seed = options.first_seed + static_cast<uint32_t>(run);
      SimRunResult result;
      if (!RunSimLocalization(seeded, world, map, localization, &result, &error)) {
        std::fprintf(stderr, "\nerror: %s\n", error.c_str());
        return 1;
      }
      const SimRobotResult& lost = result.robots[static_cast<size_t>(base.lost_robot)];
      Tally(result, lost, collaborate, options.target_delay,
            collaborate ? &collaborative : &independent);
      if (run == options.trace_run) PrintTrace(lost, collaborate);
      if (run == 0) {
        for (const SimRobotResult& robot : result.robots) {
          ErrorSeries series = robot.position_error;
          series.name = robot.name + (collaborate ? "_collaborative" : "_alone");
          if (collaborate || &robot == &lost) plot_series.push_back(series);
        }
      }
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("\nsummary (%d runs, %.1f s wall):\n", options.runs, seconds);
  PrintSummary(collaborative, independent, options.target_delay);
  if (!options.plot_path.empty() && !WritePlot(options, plot_series)) return 1;
  return 0;
}

}  // namespace fleetmap
